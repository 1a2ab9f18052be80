// 3DTILES_batch_table_hierarchy, flattened: every property of every hierarchy class becomes one column of the
// batch table, and feature f's value is that of the first instance met walking breadth-first from f up through
// its parents (its own class first, then the nearest ancestors'); a feature whose instance and ancestors lack the
// property reads Null. One table keeps a pick's answer a row read; the price is that an ancestor's value is
// repeated per feature (bounded by the encoded size). A hierarchy name that is also a batch table property is
// left out (the batch table's is kept). Classes' names (isClass, getExactClassName) are not kept.
#include "loaders/tiles/internal/BatchTable.h"

#include "loaders/gltf/internal/GltfDetail.h"  // fail, at

#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace sg::tiles::batch {
namespace {

using gltf::at;
using gltf::fail;
using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

// Instances visited in the walks from all features, at most: a deep hierarchy under many features costs
// features x depth, which this bounds.
constexpr uint64_t kMaxSteps = uint64_t(1) << 26;

std::string str(uint64_t v) { return std::to_string(v); }

// `n` unsigned integers, each below `limit`: a JSON array or a {byteOffset, componentType} reference (UNSIGNED_BYTE,
// UNSIGNED_SHORT (the default) or UNSIGNED_INT). Checked to be there before anything is allocated for them.
std::vector<uint32_t> readIds(const Columns& c, const json& j, uint64_t n, uint64_t limit, const std::string& path) {
    std::vector<uint32_t> ids;
    if (j.is_array()) {
        if (j.size() < n) fail(c.file, path, "has " + str(j.size()) + " values, fewer than " + str(n));
        ids.reserve(size_t(n));
        for (uint64_t i = 0; i < n; ++i) {
            const json& v = j[size_t(i)];
            if (!v.is_number_unsigned() || v.get<uint64_t>() >= limit)
                fail(c.file, at(path, size_t(i)), "must be an integer in [0, " + str(limit) + ")");
            ids.push_back(uint32_t(v.get<uint64_t>()));
        }
        return ids;
    }
    if (!j.is_object()) fail(c.file, path, "must be an array or a reference to the binary body");
    const auto ct = j.find("componentType");
    const ComponentType type = ct == j.end()     ? ComponentType::UInt16
                               : ct->is_string() ? componentOf(ct->get<std::string>())
                                                 : ComponentType::None;
    if (type != ComponentType::UInt8 && type != ComponentType::UInt16 && type != ComponentType::UInt32)
        fail(c.file, path + ".componentType", "must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    const uint64_t o = c.binaryOffset(j, type, 1, n, path);
    ids.reserve(size_t(n));
    for (uint64_t i = 0; i < n; ++i) {
        const uint64_t v = jsonElement(c.binary.data + o, type, 1, i).get<uint64_t>();
        if (v >= limit) fail(c.file, path, "value " + str(v) + " at " + str(i) + " is not below " + str(limit));
        ids.push_back(uint32_t(v));
    }
    return ids;
}

// A hierarchy class: its properties (index into the flattened ones) and their values, one per instance.
struct HClass {
    uint64_t length = 0;
    std::vector<std::pair<size_t, std::vector<const json*>>> props;
};

// The flattened properties: name, the path of the first class giving it, one value per feature.
struct Flat {
    std::vector<std::string> names, paths;
    std::map<std::string, size_t> index;
    std::deque<json> decoded;  // binary instance values made JSON (a deque: pointers into it stay valid)
};

// A class's instance property: a JSON array of `length` values or a {byteOffset, componentType, type} reference.
std::vector<const json*> instanceValues(const Columns& c, const json& v, uint64_t length, Flat& flat,
                                        const std::string& path) {
    std::vector<const json*> values;
    if (v.is_array()) {
        if (v.size() < length)
            fail(c.file, path, "has " + str(v.size()) + " values, fewer than the class's length " + str(length));
        for (uint64_t i = 0; i < length; ++i) values.push_back(&v[size_t(i)]);
        return values;
    }
    if (!v.is_object()) fail(c.file, path, "must be an array or a reference to the binary body");
    const auto ct = v.find("componentType");
    const ComponentType type =
        ct != v.end() && ct->is_string() ? componentOf(ct->get<std::string>()) : ComponentType::None;
    if (type == ComponentType::None) fail(c.file, path + ".componentType", "is missing or unknown");
    const auto t = v.find("type");
    const std::string name = t != v.end() && t->is_string() ? t->get<std::string>() : "";
    const int n = name == "SCALAR" ? 1 : name == "VEC2" ? 2 : name == "VEC3" ? 3 : name == "VEC4" ? 4 : 0;
    if (n == 0) fail(c.file, path + ".type", "is missing or not SCALAR, VEC2, VEC3 or VEC4");
    const uint64_t o = c.binaryOffset(v, type, n, length, path);
    for (uint64_t i = 0; i < length; ++i) {
        flat.decoded.push_back(jsonElement(c.binary.data + o, type, n, i));
        values.push_back(&flat.decoded.back());
    }
    return values;
}

std::vector<HClass> readClasses(const Columns& c, const json& ext, Flat& flat, const std::string& path) {
    const auto cs = ext.find("classes");
    if (cs == ext.end() || !cs->is_array()) fail(c.file, path + ".classes", "is missing or not an array");
    std::vector<HClass> classes;
    for (size_t k = 0; k < cs->size(); ++k) {
        const json& cj = (*cs)[k];
        const std::string cp = path + "." + at("classes", k);
        const auto len = cj.find("length");
        const auto inst = cj.find("instances");
        if (!cj.is_object() || len == cj.end() || !len->is_number_unsigned())
            fail(c.file, cp + ".length", "is missing or not a non-negative integer");
        if (inst == cj.end() || !inst->is_object()) fail(c.file, cp + ".instances", "is missing or not an object");
        HClass h;
        h.length = len->get<uint64_t>();
        for (const auto& [name, v] : inst->items()) {
            const std::string pp = cp + ".instances." + name;
            if (c.cls.find(name) >= 0) {
                c.warnings.push_back(pp + ": also a batch table property: the batch table's is kept");
                continue;
            }
            auto [it, added] = flat.index.emplace(name, flat.names.size());
            if (added) {
                flat.names.push_back(name);
                flat.paths.push_back(pp);
            }
            h.props.emplace_back(it->second, instanceValues(c, v, h.length, flat, pp));
        }
        classes.push_back(std::move(h));
    }
    return classes;
}

// Instance i's parents: parentIds[start[i] .. start[i + 1]) (start empty: no parents).
struct Parents {
    std::vector<uint64_t> start;
    std::vector<uint32_t> ids;
};

Parents readParents(const Columns& c, const json& ext, uint64_t n, const std::string& path) {
    Parents p;
    const auto ids = ext.find("parentIds");
    if (ids == ext.end()) return p;
    std::vector<uint32_t> counts;
    if (const auto pc = ext.find("parentCounts"); pc != ext.end())
        counts = readIds(c, *pc, n, uint64_t(1) << 32, path + ".parentCounts");
    p.start.reserve(size_t(n + 1));
    p.start.push_back(0);
    for (uint64_t i = 0; i < n; ++i) p.start.push_back(p.start.back() + (counts.empty() ? 1 : counts[size_t(i)]));
    p.ids = readIds(c, *ids, p.start.back(), n, path + ".parentIds");
    return p;
}

}  // namespace

void addHierarchy(Columns& c, const json& ext, const std::string& path) {
    const auto il = ext.find("instancesLength");
    if (il == ext.end() || !il->is_number_unsigned() || il->get<uint64_t>() < c.count)
        fail(c.file, path + ".instancesLength", "is missing or less than batchLength " + str(c.count));
    const uint64_t n = il->get<uint64_t>();
    Flat flat;
    const std::vector<HClass> classes = readClasses(c, ext, flat, path);
    const auto ci = ext.find("classIds");
    if (ci == ext.end()) fail(c.file, path + ".classIds", "is missing");
    const std::vector<uint32_t> classIds = readIds(c, *ci, n, classes.size(), path + ".classIds");
    // An instance's index in its class: how many of its class came before it.
    std::vector<uint64_t> seen(classes.size(), 0);
    std::vector<uint64_t> indexInClass(static_cast<size_t>(n));
    for (uint64_t i = 0; i < n; ++i) {
        const uint32_t k = classIds[size_t(i)];
        if (seen[k] >= classes[k].length)
            fail(c.file, path + ".classIds",
                 "more instances of class " + str(k) + " than its length " + str(classes[k].length));
        indexInClass[size_t(i)] = seen[k]++;
    }
    const Parents parents = readParents(c, ext, n, path);

    c.reserve(uint64_t(flat.names.size()) * c.count * sizeof(void*), path);
    std::vector<std::vector<const json*>> values(flat.names.size(), std::vector<const json*>(c.count, nullptr));
    std::vector<uint32_t> stamp(static_cast<size_t>(n),
                                0);  // feature f + 1 once its walk has queued the instance: no cycle loops
    std::vector<uint32_t> queue;
    uint64_t steps = 0;
    for (uint32_t f = 0; f < c.count; ++f) {
        queue.assign(1, f);
        stamp[f] = f + 1;
        for (size_t q = 0; q < queue.size(); ++q) {
            if (++steps > kMaxSteps) fail(c.file, path + ".parentIds", "the hierarchy is too deep to walk");
            const uint32_t i = queue[q];
            for (const auto& [prop, vals] : classes[classIds[i]].props) {
                const json*& v = values[prop][f];
                if (!v || v->is_null()) v = vals[size_t(indexInClass[i])];
            }
            if (parents.start.empty()) continue;
            for (uint64_t k = parents.start[i]; k < parents.start[i + 1]; ++k) {
                const uint32_t parent = parents.ids[size_t(k)];
                if (stamp[parent] != f + 1) {  // itself (no parent) or already queued
                    stamp[parent] = f + 1;
                    queue.push_back(parent);
                }
            }
        }
    }
    for (size_t p = 0; p < flat.names.size(); ++p) c.addJson(flat.names[p], values[p], flat.paths[p]);
}

}  // namespace sg::tiles::batch
