// glTF `extras` as the conversion reads them: an application's properties, sgkit's own object, and its values
// checked (a value of the wrong type refuses the file, naming its path).
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>
#include <limits>

namespace sg::gltf {

using tinygltf::Value;

GltfProperties properties(const Value& extras) {
    GltfProperties p;
    if (!extras.IsObject()) return p;
    for (const std::string& k : extras.Keys()) {
        if (k == kExtrasKey) continue;
        const Value& v = extras.Get(k);
        if (v.IsString())
            p.strings[k] = v.Get<std::string>();
        else if (v.IsNumber() && std::isfinite(v.GetNumberAsDouble()))
            p.numbers[k] = v.GetNumberAsDouble();
    }
    return p;
}

const Value* sgkitExtras(const Value& extras) {
    if (!extras.IsObject() || !extras.Has(kExtrasKey)) return nullptr;
    const Value& v = extras.Get(kExtrasKey);
    return v.IsObject() ? &v : nullptr;
}

double Converter::number(const Value& o, const char* key, const std::string& path, double def) {
    if (!o.Has(key)) return def;
    const Value& v = o.Get(key);
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) bad(path + "." + key, "must be a finite number");
    return v.GetNumberAsDouble();
}

std::string Converter::string(const Value& o, const char* key, const std::string& path, const std::string& def) {
    if (!o.Has(key)) return def;
    const Value& v = o.Get(key);
    if (!v.IsString()) bad(path + "." + key, "must be a string");
    return v.Get<std::string>();
}

std::vector<double> Converter::numbers(const Value& v, const std::string& path, size_t n) {
    if (!v.IsArray() || (n && v.ArrayLen() != n))
        bad(path, n ? "must be an array of " + std::to_string(n) + " numbers" : "must be an array of numbers");
    std::vector<double> r;
    for (size_t i = 0; i < v.ArrayLen(); ++i) {
        const Value& e = v.Get(int(i));
        if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble())) bad(at(path, i), "must be a finite number");
        r.push_back(e.GetNumberAsDouble());
    }
    return r;
}

float Converter::toFloat(double v, const std::string& path) {
    if (!(std::abs(v) <= double(std::numeric_limits<float>::max()))) bad(path, "is out of float range");
    return float(v);
}

dvec3 Converter::vec(const Value& o, const char* key, const std::string& path) {
    const std::vector<double> v = numbers(o.Get(key), path + "." + key, 3);
    return dvec3(v[0], v[1], v[2]);
}

}  // namespace sg::gltf
