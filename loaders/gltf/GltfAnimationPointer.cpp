// KHR_animation_pointer channels: a JSON pointer into the file bound to what was built from it. Node properties
// become ordinary channels; material factors replace the Geometries' materials with changed copies; lights and
// cameras are written into GltfScene::animatedLights and animatedCameras.
#include "loaders/gltf/internal/GltfConverter.h"

#include <algorithm>
#include <cmath>

namespace sg::gltf {

namespace {

// A JSON pointer's reference tokens ("/materials/0/emissiveFactor": materials, 0, emissiveFactor); empty when it does
// not start with '/'. The properties read here have no '~' or '/' in their names, so escapes are left as they are
// (and then match nothing).
std::vector<std::string> tokens(const std::string& pointer) {
    std::vector<std::string> out;
    if (pointer.empty() || pointer[0] != '/') return out;
    size_t b = 1;
    while (true) {
        const size_t e = pointer.find('/', b);
        out.push_back(pointer.substr(b, e == std::string::npos ? std::string::npos : e - b));
        if (e == std::string::npos) return out;
        b = e + 1;
    }
}

// An array index token: its value (held to int's range), or -1 when it is not one (RFC 6901: digits, no leading 0).
int indexToken(const std::string& t) {
    if (t.empty() || (t.size() > 1 && t[0] == '0') || !std::all_of(t.begin(), t.end(), ::isdigit)) return -1;
    return t.size() > 9 ? 0x7fffffff : std::stoi(t);
}

std::string join(const std::vector<std::string>& t, size_t from) {
    std::string s;
    for (size_t k = from; k < t.size(); ++k) s += (k > from ? "/" : "") + t[k];
    return s;
}

enum class MaterialField { BaseColor, Metallic, Roughness, Emissive, AlphaCutoff };

// Writes the sampled values into `mat` (when given); whether they differ from what `cur` holds. `strength`:
// KHR_materials_emissive_strength, which the material's emissive factor holds multiplied in.
bool writeField(const Material& cur, Material* mat, MaterialField f, const double* v, float strength) {
    switch (f) {
        case MaterialField::BaseColor: {
            const vec4 c = vec4(float(v[0]), float(v[1]), float(v[2]), float(v[3]));
            if (mat) mat->baseColor = c;
            return c != cur.baseColor;
        }
        case MaterialField::Emissive: {
            const vec3 e = vec3(float(v[0]), float(v[1]), float(v[2])) * strength;
            if (mat) mat->pbr.emissiveFactor = e;
            return e != cur.pbr.emissiveFactor;
        }
        case MaterialField::Metallic:
            if (mat) mat->pbr.metallic = float(v[0]);
            return float(v[0]) != cur.pbr.metallic;
        case MaterialField::Roughness:
            if (mat) mat->pbr.roughness = float(v[0]);
            return float(v[0]) != cur.pbr.roughness;
        case MaterialField::AlphaCutoff:
            if (mat) mat->alphaCutoff = float(v[0]);
            return float(v[0]) != cur.alphaCutoff;
    }
    return false;
}

// A changed copy of each distinct material of `users` that the values change, set on the Geometries that had it.
void setMaterials(const std::vector<ref_ptr<Geometry>>& users, MaterialField f, const double* v, float strength) {
    std::vector<std::pair<ref_ptr<Material>, ref_ptr<Material>>> made;  // old (held while replaced), its copy
    for (const ref_ptr<Geometry>& g : users) {
        Material* cur = g->material();
        if (!cur || !writeField(*cur, nullptr, f, v, strength)) continue;
        auto it = std::find_if(made.begin(), made.end(), [&](const auto& p) { return p.first.get() == cur; });
        if (it == made.end()) {
            ref_ptr<Material> copy = cur->copy();
            writeField(*cur, copy.get(), f, v, strength);
            made.emplace_back(ref_ptr<Material>(cur), copy);
            it = made.end() - 1;
        }
        g->setMaterial(it->second);
    }
}

float clampTo(double v, float lo, float hi) { return std::isfinite(v) ? std::clamp(float(v), lo, hi) : lo; }

}  // namespace

void Converter::pointerChannel(AnimationRead& r, size_t c) {
    const tinygltf::AnimationChannel& gc = r.ga.channels[c];
    const std::string cp = r.path("channels", c);
    const auto x = gc.target_extensions.find(kAnimationPointer);
    if (x == gc.target_extensions.end() || !x->second.Has("pointer") || !x->second.Get("pointer").IsString()) {
        warn(cp + ".target", "path 'pointer' without a KHR_animation_pointer pointer: channel skipped");
        return;
    }
    const std::string where = cp + ".target.extensions." + kAnimationPointer + ".pointer";
    const std::string pointer = x->second.Get("pointer").Get<std::string>();
    const std::vector<std::string> t = tokens(pointer);
    const int i = t.size() >= 2 ? indexToken(t[1]) : -1;
    const size_t n = t.size();
    if (n == 3 && t[0] == "nodes" && i >= 0 &&
        (t[2] == "translation" || t[2] == "rotation" || t[2] == "scale" || t[2] == "weights")) {
        nodeChannel(r, c, i, t[2], where);
    } else if (n >= 3 && t[0] == "materials" && i >= 0) {
        materialChannel(r, c, size_t(i), join(t, 2), where);
    } else if (n >= 5 && t[0] == "extensions" && t[1] == "KHR_lights_punctual" && t[2] == "lights" &&
               indexToken(t[3]) >= 0) {
        lightChannel(r, c, size_t(indexToken(t[3])), join(t, 4), where);
    } else if (n == 4 && t[0] == "cameras" && i >= 0) {
        cameraChannel(r, c, size_t(i), t[2], t[3], where);
    } else {
        warn(where, "'" + pointer + "' is not a property sgkit animates: channel skipped");
    }
}

void Converter::materialChannel(AnimationRead& r, size_t c, size_t mat, const std::string& property,
                                const std::string& where) {
    if (mat >= m.materials.size())
        bad(where, "material " + std::to_string(mat) + " does not exist (" + std::to_string(m.materials.size()) +
                       " materials)");
    const std::string pointer = "/materials/" + std::to_string(mat) + "/" + property;
    MaterialField f;
    if (property == "pbrMetallicRoughness/baseColorFactor")
        f = MaterialField::BaseColor;
    else if (property == "pbrMetallicRoughness/metallicFactor")
        f = MaterialField::Metallic;
    else if (property == "pbrMetallicRoughness/roughnessFactor")
        f = MaterialField::Roughness;
    else if (property == "emissiveFactor")
        f = MaterialField::Emissive;
    else if (property == "alphaCutoff")
        f = MaterialField::AlphaCutoff;
    else
        return warn(where, "'" + pointer + "' is not a property sgkit animates: channel skipped");
    const tinygltf::Material& gm = m.materials[mat];
    if (f == MaterialField::AlphaCutoff && gm.alphaMode != "MASK")
        return warn(where, "material " + std::to_string(mat) + " is not alphaMode MASK, so its alphaCutoff does " +
                               "nothing: channel skipped");
    auto users = materialUsers.find(int(mat));
    if (users == materialUsers.end())
        return warn(where, "material " + std::to_string(mat) + " is on no Geometry of the scene: channel skipped");
    float strength = 1.0f;  // as material() applies it; a bad value was warned about there
    const auto x = gm.extensions.find("KHR_materials_emissive_strength");
    if (x != gm.extensions.end() && x->second.Has("emissiveStrength") && x->second.Get("emissiveStrength").IsNumber()) {
        const double e = x->second.Get("emissiveStrength").GetNumberAsDouble();
        if (std::isfinite(e) && e >= 0.0 && e < 1e30) strength = float(e);
    }
    const bool vector = f == MaterialField::BaseColor || f == MaterialField::Emissive;
    const uint32_t width = f == MaterialField::BaseColor ? 4 : f == MaterialField::Emissive ? 3 : 1;
    AnimationChannel ch;
    ch.path = AnimationPath::Property;
    ch.target = pointer;
    ch.sampler = channelSampler(r, c,
                                !vector                         ? TINYGLTF_TYPE_SCALAR
                                : f == MaterialField::BaseColor ? TINYGLTF_TYPE_VEC4
                                                                : TINYGLTF_TYPE_VEC3,
                                width, Outputs::Integers, pointer);
    ch.set = [geometries = users->second, f, strength](const double* v, uint32_t) {
        setMaterials(geometries, f, v, strength);
    };
    r.anim.channels.push_back(std::move(ch));
}

void Converter::lightChannel(AnimationRead& r, size_t c, size_t light, const std::string& property,
                             const std::string& where) {
    if (light >= m.lights.size())
        bad(where,
            "light " + std::to_string(light) + " does not exist (" + std::to_string(m.lights.size()) + " lights)");
    const std::string pointer = "/extensions/KHR_lights_punctual/lights/" + std::to_string(light) + "/" + property;
    enum { Color, Intensity, Range, Inner, Outer } p;
    if (property == "color")
        p = Color;
    else if (property == "intensity")
        p = Intensity;
    else if (property == "range")
        p = Range;
    else if (property == "spot/innerConeAngle")
        p = Inner;
    else if (property == "spot/outerConeAngle")
        p = Outer;
    else
        return warn(where, "'" + pointer + "' is not a property sgkit animates: channel skipped");
    if ((p == Inner || p == Outer) && m.lights[light].type != "spot")
        bad(where, "light " + std::to_string(light) + " is not a spot light");
    const auto found = lightEntries.find(int(light));
    if (found == lightEntries.end())
        return warn(where, "light " + std::to_string(light) + " is on no node of the scene: channel skipped");
    if (!out.animatedLights) out.animatedLights = std::make_shared<std::vector<PunctualLight>>(out.lights);
    AnimationChannel ch;
    ch.path = AnimationPath::Property;
    ch.target = pointer;
    ch.sampler = channelSampler(r, c, p == Color ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_SCALAR, p == Color ? 3 : 1,
                                Outputs::Integers, pointer);
    // Held to what the renderer accepts (Renderer::setPunctualLights): a cubic spline may overshoot.
    ch.set = [lights = out.animatedLights, entries = found->second, p](const double* v, uint32_t) {
        constexpr float kMax = 1e30f, kHalfPi = 1.5707964f;
        for (size_t e : entries) {
            PunctualLight& l = (*lights)[e];
            if (p == Color) l.color = vec3(clampTo(v[0], 0, kMax), clampTo(v[1], 0, kMax), clampTo(v[2], 0, kMax));
            if (p == Intensity) l.intensity = clampTo(v[0], 0, kMax);
            if (p == Range) l.range = clampTo(v[0], 0, kMax);
            if (p == Outer) l.outerConeAngle = clampTo(v[0], 1e-4f, kHalfPi);
            if (p == Inner) l.innerConeAngle = clampTo(v[0], 0, kHalfPi);
            if (l.innerConeAngle >= l.outerConeAngle) l.innerConeAngle = std::nextafter(l.outerConeAngle, 0.0f);
        }
    };
    r.anim.channels.push_back(std::move(ch));
}

void Converter::cameraChannel(AnimationRead& r, size_t c, size_t cam, const std::string& kind,
                              const std::string& property, const std::string& where) {
    if (cam >= m.cameras.size())
        bad(where,
            "camera " + std::to_string(cam) + " does not exist (" + std::to_string(m.cameras.size()) + " cameras)");
    const std::string pointer = "/cameras/" + std::to_string(cam) + "/" + kind + "/" + property;
    const bool perspective = kind == "perspective";
    const bool known =
        perspective ? property == "yfov" || property == "znear" || property == "zfar" || property == "aspectRatio"
                    : kind == "orthographic" &&
                          (property == "xmag" || property == "ymag" || property == "znear" || property == "zfar");
    if (!known) return warn(where, "'" + pointer + "' is not a property sgkit animates: channel skipped");
    if (m.cameras[cam].type != kind) bad(where, "camera " + std::to_string(cam) + " is not " + kind);
    const auto found = cameraEntries.find(int(cam));
    if (found == cameraEntries.end())
        return warn(where, "camera " + std::to_string(cam) + " is on no node of the scene: channel skipped");
    if (!out.animatedCameras) out.animatedCameras = std::make_shared<std::vector<GltfCamera>>(out.cameras);
    AnimationChannel ch;
    ch.path = AnimationPath::Property;
    ch.target = pointer;
    ch.sampler = channelSampler(r, c, TINYGLTF_TYPE_SCALAR, 1, Outputs::Integers, pointer);
    ch.set = [cameras = out.animatedCameras, entries = found->second, property](const double* v, uint32_t) {
        if (!std::isfinite(v[0])) return;
        for (size_t e : entries) {
            GltfCamera& k = (*cameras)[e];
            if (property == "yfov") k.yfovDegrees = std::clamp(glm::degrees(v[0]), 1e-3, 179.0);  // as camera()
            if (property == "aspectRatio") k.aspect = std::max(v[0], 0.0);
            if (property == "znear") k.znear = k.perspective ? std::max(v[0], 1e-9) : v[0];
            if (property == "zfar") k.zfar = v[0];
            if (property == "xmag") k.xmag = v[0];
            if (property == "ymag") k.ymag = v[0];
        }
    };
    r.anim.channels.push_back(std::move(ch));
}

}  // namespace sg::gltf
