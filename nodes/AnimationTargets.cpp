// Animation::validate(): its samplers and the nodes its channels drive. Defined with the node types, as a weights
// channel's width is its Geometries' morph target count (sg/core reads no node type).
#include "nodes/Geometry.h"
#include "nodes/internal/MorphGeometries.h"
#include "sg/core/Animation.h"

#include <stdexcept>
#include <string>

namespace sg {

namespace {

// The morph target count of the first Geometry a weights channel on `n` drives; -1: none.
long morphTargetCount(Node& n) {
    long count = -1;
    forEachMorphGeometry(n, [&](Geometry& g) {
        if (count < 0) count = g.mesh() ? long(g.mesh()->morphTargets().size()) : 0;
    });
    return count;
}

// What is wrong with channel c, or empty.
std::string channelProblem(const Animation& a, const AnimationChannel& c) {
    if (c.sampler >= a.samplers.size())
        return "sampler " + std::to_string(c.sampler) + " is past the " + std::to_string(a.samplers.size()) +
               " samplers";
    const uint32_t width = a.samplers[c.sampler].width;
    const std::string what = std::string(pathName(c.path)) + " channel";
    const auto widthProblem = [&](long expected, const std::string& why) {
        return long(width) == expected ? std::string() : what + " has width " + std::to_string(width) + ", " + why;
    };
    switch (c.path) {
        case AnimationPath::Translation:
        case AnimationPath::Rotation:
        case AnimationPath::Scale:
            if (!c.node) return what + " has no node";
            if (c.node->kind() != NodeKind::Transform)
                return what + " drives " + c.node->describe() + ", which is not a Transform";
            return widthProblem(c.path == AnimationPath::Rotation ? 4 : 3,
                                c.path == AnimationPath::Rotation ? "expected 4 (x y z w)" : "expected 3");
        case AnimationPath::Weights: {
            if (!c.node) return what + " has no node";
            const long targets = morphTargetCount(*c.node);
            if (targets < 0) return what + " drives " + c.node->describe() + ", which has no Geometry";
            return widthProblem(targets, "its mesh has " + std::to_string(targets) + " morph targets");
        }
        case AnimationPath::Property:
            if (!c.set) return what + " (" + c.target + ") has no setter";
            return {};
    }
    return "unknown path";
}

}  // namespace

void Animation::validate() const {
    const std::string fn = "Animation::validate(): " + (name.empty() ? std::string("animation") : "'" + name + "'");
    for (size_t i = 0; i < samplers.size(); ++i) {
        try {
            samplers[i].validate();
        } catch (const std::invalid_argument& e) {
            const std::string why = e.what(), prefix = "AnimationSampler::validate(): ";
            throw std::invalid_argument(fn + ": samplers[" + std::to_string(i) + "]: " +
                                        (why.compare(0, prefix.size(), prefix) == 0 ? why.substr(prefix.size()) : why));
        }
    }
    for (size_t i = 0; i < channels.size(); ++i) {
        const std::string why = channelProblem(*this, channels[i]);
        if (!why.empty()) throw std::invalid_argument(fn + ": channels[" + std::to_string(i) + "]: " + why);
    }
}

}  // namespace sg
