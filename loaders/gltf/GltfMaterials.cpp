// glTF materials to sgkit's: the metallic-roughness model and its textures (images decoded once each, samplers,
// KHR_texture_transform), and materials sgkit wrote from its classic shading read back as that.
#include "loaders/gltf/internal/GltfConverter.h"

#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace sg::gltf {

ref_ptr<Texture> Converter::texture(int t, const std::string& path) {
    const tinygltf::Texture& gt = m.textures[size_t(t)];
    if (gt.source < 0) return {};
    const Sampler s = sampler(gt.sampler);
    const auto key = std::make_pair(gt.source, samplerKey(s));
    const auto made = textures.find(key);
    if (made != textures.end()) return made->second;
    ref_ptr<Texture> tex = image(gt.source, path);
    if (tex && imageTaken[size_t(gt.source)])  // a Texture holds its pixels: another sampler needs a copy
        tex = make<Texture>(tex->width(), tex->height(), tex->rgba());
    if (tex) {
        imageTaken[size_t(gt.source)] = true;
        tex->sampler = s;
    }
    return textures[key] = tex;
}

ref_ptr<Texture> Converter::image(int img, const std::string& path) {
    if (imageDone[size_t(img)]) return images[size_t(img)];
    imageDone[size_t(img)] = true;
    const tinygltf::Image& im = m.images[size_t(img)];
    const unsigned char* bytes = im.image.data();
    size_t size = im.image.size();
    if (im.bufferView != -1) {
        const tinygltf::BufferView& v = m.bufferViews[size_t(im.bufferView)];
        bytes = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset;
        size = v.byteLength;
    }
    const std::string ip = at("images", size_t(img));
    int w = 0, h = 0, n = 0;
    if (!bytes || size == 0 || size > 0x7fffffff || !stbi_info_from_memory(bytes, int(size), &w, &h, &n)) {
        warn(ip, "image cannot be decoded, texture skipped (used by " + path + ")");
        return {};
    }
    if (w <= 0 || h <= 0 || (long long)w * h > kMaxImagePixels) {
        warn(ip, "image of " + std::to_string(w) + " x " + std::to_string(h) + " pixels is too large, texture skipped");
        return {};
    }
    unsigned char* px = stbi_load_from_memory(bytes, int(size), &w, &h, &n, 4);
    if (!px) {
        warn(ip, std::string("image cannot be decoded (") + stbi_failure_reason() + "), texture skipped");
        return {};
    }
    // Rows top to bottom: row 0 is glTF's v = 0, which is also the Renderer's first texture row.
    std::vector<uint8_t> rgba(px, px + size_t(w) * size_t(h) * 4);
    stbi_image_free(px);
    images[size_t(img)] = make<Texture>(w, h, std::move(rgba));
    return images[size_t(img)];
}

namespace {

// glTF's wrap and filter enums (OpenGL's values) as Sampler's; false for a value outside them.
bool toWrap(int v, Sampler::Wrap& w) {
    switch (v) {
        case 10497: w = Sampler::Wrap::Repeat; return true;
        case 33648: w = Sampler::Wrap::MirroredRepeat; return true;
        case 33071: w = Sampler::Wrap::ClampToEdge; return true;
        default: return false;
    }
}

bool toFilter(int v, bool minifying, Sampler::Filter& f) {
    using F = Sampler::Filter;
    constexpr F kMipmapped[4] = {F::NearestMipmapNearest, F::LinearMipmapNearest, F::NearestMipmapLinear,
                                 F::LinearMipmapLinear};  // 9984 to 9987
    if (v == 9728 || v == 9729) {
        f = v == 9728 ? F::Nearest : F::Linear;
        return true;
    }
    if (!minifying || v < 9984 || v > 9987) return false;
    f = kMipmapped[v - 9984];
    return true;
}

}  // namespace

Sampler Converter::sampler(int i) {
    Sampler s;
    if (i < 0) return s;
    const auto done = samplers.find(i);
    if (done != samplers.end()) return done->second;
    const tinygltf::Sampler& gs = m.samplers[size_t(i)];
    const std::string sp = at("samplers", size_t(i));
    if (!toWrap(gs.wrapS, s.wrapS))
        warn(sp + ".wrapS", std::to_string(gs.wrapS) + " is not a wrap mode (10497, 33648, 33071), REPEAT used");
    if (!toWrap(gs.wrapT, s.wrapT))
        warn(sp + ".wrapT", std::to_string(gs.wrapT) + " is not a wrap mode (10497, 33648, 33071), REPEAT used");
    // -1: not given (tinygltf's mark); the default stays.
    if (gs.magFilter != -1 && !toFilter(gs.magFilter, false, s.magFilter))
        warn(sp + ".magFilter",
             std::to_string(gs.magFilter) + " is not a magnification filter (9728, 9729), LINEAR used");
    if (gs.minFilter != -1 && !toFilter(gs.minFilter, true, s.minFilter))
        warn(sp + ".minFilter",
             std::to_string(gs.minFilter) +
                 " is not a minification filter (9728, 9729, 9984 to 9987), LINEAR_MIPMAP_LINEAR used");
    return samplers[i] = s;
}

void Converter::textureTransform(const tinygltf::ExtensionMap& ext, const std::string& path, TextureSlot& slot) {
    const auto it = ext.find("KHR_texture_transform");
    if (it == ext.end() || !it->second.IsObject()) return;
    const Value& t = it->second;
    bool ok = true;
    auto number = [&](const Value& v, double def) {
        const double x = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
        ok = ok && std::isfinite(x) && std::abs(x) < 1e30;
        return ok ? x : def;
    };
    auto pair = [&](const char* key, double def) {
        if (!t.Has(key)) return dvec2(def);
        const Value& v = t.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2) ok = false;
        return ok ? dvec2(number(v.Get(0), def), number(v.Get(1), def)) : dvec2(def);
    };
    const dvec2 o = pair("offset", 0.0), sc = pair("scale", 1.0);
    const double r = t.Has("rotation") ? number(t.Get("rotation"), 0.0) : 0.0;
    if (!ok) {
        warn(path + ".extensions.KHR_texture_transform",
             "offset, rotation or scale is not a finite number (or an array of the wrong length), ignored");
        return;
    }
    const float c = float(std::cos(r)), s = float(std::sin(r));
    // The extension's rows are [sx c, sy s, ox] and [-sx s, sy c, oy]; glm's constructor takes columns.
    slot.transform = mat3(vec3(float(sc.x) * c, -float(sc.x) * s, 0.0f), vec3(float(sc.y) * s, float(sc.y) * c, 0.0f),
                          vec3(float(o.x), float(o.y), 1.0f));
    if (t.Has("texCoord") && t.Get("texCoord").IsInt()) slot.texCoord = t.Get("texCoord").Get<int>();
}

TextureSlot Converter::slot(int index, int texCoord, const tinygltf::ExtensionMap& ext, const std::string& path) {
    TextureSlot t;
    if (index < 0) return t;
    t.texCoord = texCoord;
    textureTransform(ext, path, t);
    if (t.texCoord != 0 && t.texCoord != 1) {
        warn(path, "texCoord " + std::to_string(t.texCoord) + " is not supported (0 and 1 are), texture skipped");
        return TextureSlot{};
    }
    t.texture = texture(index, path);
    return t;
}

void Converter::classic(const Value& x, const std::string& path, Material& mat) {
    if (string(x, "shading", path, "") != "classic") return;
    mat.physical = false;
    mat.specular = toFloat(number(x, "specular", path, 0.0), path + ".specular");
    mat.shininess = toFloat(number(x, "shininess", path, 32.0), path + ".shininess");
    if (x.Has("bakedLight")) {
        if (!x.Get("bakedLight").IsBool()) bad(path + ".bakedLight", "must be true or false");
        mat.bakedLight = x.Get("bakedLight").Get<bool>();
    }
    mat.doubleSided = true;
}

bool Converter::requiresExtension(const char* extension) const {
    const auto& r = m.extensionsRequired;
    return std::find(r.begin(), r.end(), extension) != r.end();
}

void Converter::approximate(const tinygltf::Material& gm, const std::string& mp, Material& mat) {
    // Only where the file requires them: a file that merely uses them has a metallic-roughness fallback.
    const auto sgx = gm.extensions.find("KHR_materials_pbrSpecularGlossiness");
    if (sgx != gm.extensions.end() && sgx->second.IsObject() && requiresExtension(sgx->first.c_str())) {
        specularGlossiness(sgx->second, mp + ".extensions." + sgx->first, mat);
        return;
    }
    const auto t = gm.extensions.find("KHR_techniques_webgl");
    const bool technique = (t != gm.extensions.end() && requiresExtension(t->first.c_str())) ||
                           (gm.additionalValues.count("technique") && requiresExtension("KHR_technique_webgl"));
    if (!technique) return;
    // A shader program sgkit does not run: a plain diffuse surface, of the colour or texture a "diffuse" value
    // gives (WebGL techniques were mostly Blinn-Phong: the diffuse part is the nearest).
    mat.pbr.metallic = 0.0f;
    mat.pbr.roughness = 1.0f;
    if (t == gm.extensions.end() || !t->second.IsObject() || !t->second.Has("values")) return;
    const Value& values = t->second.Get("values");
    if (!values.IsObject()) return;
    for (const std::string& key : values.Keys()) {
        std::string lower = key;
        for (char& ch : lower) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        if (lower.find("diffuse") == std::string::npos) continue;
        diffuse(values.Get(key), mp + ".extensions.KHR_techniques_webgl.values." + key, mat);
        return;
    }
}

void Converter::diffuse(const Value& v, const std::string& path, Material& mat) {
    if (v.IsObject() && v.Has("index") && v.Get("index").IsInt()) {  // a texture reference
        const int index = v.Get("index").Get<int>();
        if (index < 0 || size_t(index) >= m.textures.size()) {
            warn(path + ".index", "texture " + std::to_string(index) + " does not exist, ignored");
            return;
        }
        const int texCoord = v.Has("texCoord") && v.Get("texCoord").IsInt() ? v.Get("texCoord").Get<int>() : 0;
        tinygltf::ExtensionMap ext;
        if (v.Has("extensions") && v.Get("extensions").IsObject())
            for (const std::string& k : v.Get("extensions").Keys()) ext[k] = v.Get("extensions").Get(k);
        const TextureSlot s = slot(index, texCoord, ext, path);
        mat.texture = s.texture;
        mat.texCoord = s.texCoord;
        mat.textureTransform = s.transform;
    } else if (v.IsArray() && (v.ArrayLen() == 3 || v.ArrayLen() == 4)) {  // a colour
        vec4 c(1.0f);
        for (int k = 0; k < int(v.ArrayLen()); ++k) {
            const double x = v.Get(k).IsNumber() ? v.Get(k).GetNumberAsDouble() : std::nan("");
            if (!(x >= 0.0 && x <= 1.0)) {
                warn(path, "is not a colour of numbers in [0, 1], ignored");
                return;
            }
            c[k] = float(x);
        }
        mat.baseColor = c;
    }
}

void Converter::specularGlossiness(const Value& x, const std::string& path, Material& mat) {
    // The extension's diffuse as the base colour of a dielectric, its glossiness as smoothness; the specular
    // colour, which metallic-roughness cannot hold, is dropped.
    mat.baseColor = vec4(1.0f);
    mat.texture = {};
    mat.texCoord = 0;
    mat.textureTransform = mat3(1.0f);
    if (x.Has("diffuseFactor")) diffuse(x.Get("diffuseFactor"), path + ".diffuseFactor", mat);
    if (x.Has("diffuseTexture")) diffuse(x.Get("diffuseTexture"), path + ".diffuseTexture", mat);
    double gloss = 1.0;
    if (x.Has("glossinessFactor")) {
        const Value& g = x.Get("glossinessFactor");
        const double v = g.IsNumber() ? g.GetNumberAsDouble() : -1.0;
        if (v >= 0.0 && v <= 1.0)
            gloss = v;
        else
            warn(path + ".glossinessFactor", "is not a number in [0, 1], ignored");
    }
    mat.pbr.metallic = 0.0f;
    mat.pbr.roughness = float(1.0 - gloss);
    mat.pbr.metallicRoughness = TextureSlot{};
}

ref_ptr<Material> Converter::material(int i) {
    if (i < 0) return {};
    if (materialDone[size_t(i)]) return materials[size_t(i)];
    materialDone[size_t(i)] = true;
    const tinygltf::Material& gm = m.materials[size_t(i)];
    const auto& pbr = gm.pbrMetallicRoughness;
    const std::string mp = at("materials", size_t(i));
    vec4 c(1.0f);
    for (size_t k = 0; k < 4 && k < pbr.baseColorFactor.size(); ++k) c[int(k)] = float(pbr.baseColorFactor[k]);
    auto mat = make<Material>(c);
    mat->physical = true;
    const TextureSlot base = slot(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                  pbr.baseColorTexture.extensions, mp + ".pbrMetallicRoughness.baseColorTexture");
    mat->texture = base.texture;
    mat->texCoord = base.texCoord;
    mat->textureTransform = base.transform;
    PhysicalMaterial& p = mat->pbr;
    p.metallic = float(pbr.metallicFactor);
    p.roughness = float(pbr.roughnessFactor);
    p.metallicRoughness =
        slot(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
             pbr.metallicRoughnessTexture.extensions, mp + ".pbrMetallicRoughness.metallicRoughnessTexture");
    p.normal =
        slot(gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.extensions, mp + ".normalTexture");
    p.normalScale = float(gm.normalTexture.scale);
    p.occlusion = slot(gm.occlusionTexture.index, gm.occlusionTexture.texCoord, gm.occlusionTexture.extensions,
                       mp + ".occlusionTexture");
    p.occlusionStrength = float(gm.occlusionTexture.strength);
    p.emissive = slot(gm.emissiveTexture.index, gm.emissiveTexture.texCoord, gm.emissiveTexture.extensions,
                      mp + ".emissiveTexture");
    for (size_t k = 0; k < 3 && k < gm.emissiveFactor.size(); ++k)
        p.emissiveFactor[int(k)] = float(gm.emissiveFactor[k]);
    const auto strength = gm.extensions.find("KHR_materials_emissive_strength");
    if (strength != gm.extensions.end() && strength->second.Has("emissiveStrength")) {
        const Value& v = strength->second.Get("emissiveStrength");
        const double e = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (std::isfinite(e) && e >= 0.0 && e < 1e30)
            p.emissiveFactor *= float(e);
        else
            warn(mp + ".extensions.KHR_materials_emissive_strength.emissiveStrength",
                 "is not a finite number >= 0, ignored");
    }
    approximate(gm, mp, *mat);
    mat->unlit = gm.extensions.count("KHR_materials_unlit") != 0;
    mat->doubleSided = gm.doubleSided;
    if (const Value* x = sgkitExtras(gm.extras)) classic(*x, mp + ".extras." + kExtrasKey, *mat);
    // MASK: alpha below the cutoff is cut away, the rest opaque; BLEND: blended, after the opaque items.
    if (gm.alphaMode == "MASK") mat->alphaCutoff = float(gm.alphaCutoff);
    mat->blend = gm.alphaMode == "BLEND";
    if (!mat->physical && mat->textureTransform != mat3(1.0f)) {  // the classic shading has no UV transform
        classicUv[i] = mat->textureTransform;
        mat->textureTransform = mat3(1.0f);
    }
    materials[size_t(i)] = mat;
    return mat;
}

}  // namespace sg::gltf
