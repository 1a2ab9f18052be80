// Animation: keyframed motion as glTF 2.0 defines it (its section 3.11): samplers of times and values with STEP,
// LINEAR or CUBICSPLINE interpolation, and channels that drive a node's translation, rotation or scale, a mesh's
// morph weights, or any property a setter writes (KHR_animation_pointer: materials, lights, cameras). Data only:
// AnimationPlayer (sg/scene/AnimationPlayer.h) runs them.
#pragma once
#include "sg/core/Node.h"
#include "sg/core/Ref.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace sg {

enum class Interpolation : uint8_t { Step, Linear, CubicSpline };

struct AnimationSampler {
    std::vector<float> times;  // seconds, strictly increasing (glTF's input accessor)
    // `width` floats a key (glTF's output accessor as floats, normalized integers already divided); CubicSpline keys
    // hold three groups of `width`: in-tangent, value, out-tangent.
    std::vector<float> values;
    uint32_t width = 0;
    Interpolation interpolation = Interpolation::Linear;

    // Throws std::invalid_argument naming the problem: no keys, times not finite or not increasing, a value count
    // that is not keys x width (x 3 for CubicSpline), a width of 0, a value that is not finite.
    void validate() const;
    // The `width` values at time t into out, in double, exactly as glTF's Appendix C defines them: before the first
    // key the first value, after the last the last; Step holds a key's value until the next key; Linear mixes the
    // two keys about t, and for a rotation (`rotation` true, width 4, x y z w) slerps along the shorter arc; a
    // CubicSpline is the Hermite spline of the keys' values and their tangents times the key interval, a rotation
    // normalised after. Stateless; `hint` (a key index, or null) speeds up a search that moves forward.
    void sample(double t, bool rotation, double* out, uint32_t* hint = nullptr) const;
    double start() const { return times.empty() ? 0.0 : times.front(); }
    double end() const { return times.empty() ? 0.0 : times.back(); }
};

enum class AnimationPath : uint8_t { Translation, Rotation, Scale, Weights, Property };
const char* pathName(AnimationPath p);  // glTF's names: "translation", "rotation", "scale", "weights", "pointer"

struct AnimationChannel {
    uint32_t sampler = 0;  // into Animation::samplers
    AnimationPath path = AnimationPath::Translation;
    // Translation, Rotation, Scale: a Transform (its matrix becomes T * R * S, the parts no channel drives taken
    // from its matrix when the player first applies the animation). Weights: a Geometry, or a node whose Geometries
    // below it (up to the next Transform: a glTF node's primitives) all take them.
    ref_ptr<Node> node;
    // Property: writes the sampled values (`width` of them) where the pointer says; called on the app stage.
    std::function<void(const double* values, uint32_t width)> set;
    std::string target;  // what it drives, for messages and for saveGltf: a KHR_animation_pointer, or the node name
};

class Animation : public Referenced {
public:
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    // Throws std::invalid_argument naming "channels[i]" or "samplers[i]" and the reason: a sampler that fails
    // validate(), a channel's sampler past the samplers, a node channel without a node or of the wrong kind (TRS on
    // a node that is not a Transform), a width that does not fit the path (3 for translation and scale, 4 for
    // rotation, the target count for weights), a Property channel without a setter.
    void validate() const;
    // The last key time over its samplers (the first key may be after 0: glTF times start where the file says).
    double duration() const;
};

}  // namespace sg
