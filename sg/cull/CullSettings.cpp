#include "sg/cull/CullSettings.h"

#include <stdexcept>

namespace sg {

const char* strategyName(CullStrategy s) {
    switch (s) {
        case CullStrategy::None: return "none";
        case CullStrategy::Sphere: return "sphere";
        case CullStrategy::Aabb: return "aabb";
        case CullStrategy::SphereSphere: return "sphere-sphere";
        case CullStrategy::CenterBox: return "center-box";
    }
    return "?";
}

CullStrategy parseStrategy(const std::string& name) {
    for (auto s : {CullStrategy::None, CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere,
                   CullStrategy::CenterBox})
        if (name == strategyName(s)) return s;
    throw std::invalid_argument("parseStrategy(): unknown strategy '" + name +
                                "' (none, sphere, aabb, sphere-sphere, center-box)");
}

bool isConservative(CullStrategy s) { return s != CullStrategy::CenterBox; }

const char* occlusionModeName(OcclusionMode m) {
    switch (m) {
        case OcclusionMode::Off: return "off";
        case OcclusionMode::Tree: return "tree";
        case OcclusionMode::Auto: return "auto";
    }
    return "?";
}

OcclusionMode parseOcclusionMode(const std::string& name) {
    for (auto m : {OcclusionMode::Off, OcclusionMode::Tree, OcclusionMode::Auto})
        if (name == occlusionModeName(m)) return m;
    throw std::invalid_argument("parseOcclusionMode(): unknown occlusion mode '" + name + "' (off, tree, auto)");
}

const char* occlusionMethodName(OcclusionMethod m) {
    switch (m) {
        case OcclusionMethod::Tree: return "tree";
        case OcclusionMethod::Hom: return "hom";
        case OcclusionMethod::Auto: return "auto";
    }
    return "?";
}

OcclusionMethod parseOcclusionMethod(const std::string& name) {
    for (auto m : {OcclusionMethod::Tree, OcclusionMethod::Hom, OcclusionMethod::Auto})
        if (name == occlusionMethodName(m)) return m;
    throw std::invalid_argument("parseOcclusionMethod(): unknown occlusion method '" + name + "' (tree, hom, auto)");
}

}  // namespace sg
