#include "sg/cull/CullSettings.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace sg {

namespace {
bool powerOfTwoMapSize(int v) { return v >= 8 && v <= 1024 && (v & (v - 1)) == 0; }
}  // namespace

void OcclusionSettings::validate(const char* caller) const {
    const SettingCheck c{caller};
    c.member("occlusion.mode", mode, OcclusionMode::Adaptive);
    c.member("occlusion.method", method, OcclusionMethod::Auto);
    c.share("occlusion.autoMapShare", autoMapShare);
    c.atLeast("occlusion.minOccluderPixels", minOccluderPixels, 0.0);
    c.share("occlusion.adaptiveMinGain", adaptiveMinGain);
    if (!powerOfTwoMapSize(homWidth))
        c.fail("occlusion.homWidth", settingValue((long long)homWidth), "a power of two in 8..1024");
    if (!powerOfTwoMapSize(homHeight))
        c.fail("occlusion.homHeight", settingValue((long long)homHeight), "a power of two in 8..1024");
    if (!(homOpacity > 0.0 && homOpacity <= 1.0)) c.fail("occlusion.homOpacity", settingValue(homOpacity), "in (0, 1]");
    c.range("occlusion.homObbLevels", homObbLevels, 0, 16);
    c.member("occlusion.measureOnly.cap", measureOnly.cap, OccluderCap::CenterPlane);
    c.range("occlusion.measureOnly.screenSplits", measureOnly.screenSplits, 0, 8);
}

void CullSettings::validate(const char* caller) const {
    const SettingCheck c{caller};
    c.member("strategy", strategy, CullStrategy::CenterBox);
    c.atLeast("smallFeaturePixels", smallFeaturePixels, 0.0);
    if (!(lodHysteresis >= 0.0 && lodHysteresis < 1.0))
        c.fail("lodHysteresis", settingValue(lodHysteresis), "in [0, 1)");
    c.positive("lodScale", lodScale);
    c.range("screenRectTriangles", screenRectTriangles, 1, 65536);
    c.range("measureOnly.frustumPlanes", measureOnly.frustumPlanes, 0, 0x3f);
    occlusion.validate(caller);
    if (lodBudget.enabled) lodBudget.validate(caller);
}

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
        case OcclusionMode::EveryFrame: return "every-frame";
        case OcclusionMode::Adaptive: return "adaptive";
    }
    return "?";
}

OcclusionMode parseOcclusionMode(const std::string& name) {
    for (auto m : {OcclusionMode::Off, OcclusionMode::EveryFrame, OcclusionMode::Adaptive})
        if (name == occlusionModeName(m)) return m;
    // The names before OcclusionMethod took "tree" and "auto": scripts written then keep working.
    if (name == "tree") return OcclusionMode::EveryFrame;
    if (name == "auto") return OcclusionMode::Adaptive;
    throw std::invalid_argument("parseOcclusionMode(): unknown occlusion mode '" + name +
                                "' (off, every-frame, adaptive)");
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
