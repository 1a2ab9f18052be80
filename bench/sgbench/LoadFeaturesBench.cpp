// sgbench load --features: what a tile's features cost to load. One mesh of --count boxes (12 triangles each, a
// feature each: a per-vertex _FEATURE_ID_0 of EXT_mesh_features) whose ids point into a property table of as many
// rows (FLOAT64 height, STRING name, UINT16 floors, ENUM use: EXT_structural_metadata), written by saveGltf; and the
// same mesh without features or table, and with the ids but no table. The .glb files are loaded in turn (A B C A B C
// ...) in one process: medians, and the medians of the ratios of each turn.
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/core/PropertyTableBuilder.h"
#include "sgbench/Bench.h"

#include <sys/stat.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr const char* kUses[4] = {"residential", "office", "retail", "industrial"};
uint32_t boxHeight(uint32_t k) { return 10u + (k * 2654435761u >> 7) % 51u; }

// `count` boxes on a square grid (20 m apart, 12 m wide, 10 to 60 m tall), box k's vertices feature k.
sg::ref_ptr<sg::Mesh> boxes(uint32_t count, std::vector<uint32_t>& ids) {
    const sg::ref_ptr<sg::Mesh> unit = sg::makeBoxMesh(sg::dvec3(0.0), sg::dvec3(1.0), 1);
    const auto& up = unit->positions();
    const auto& un = unit->normals();
    const size_t nv = up.size(), ni = unit->indexCount();
    const uint32_t side = std::max(1u, uint32_t(std::ceil(std::sqrt(double(count)))));
    std::vector<sg::vec3> pos, nrm;
    std::vector<uint32_t> idx;
    pos.reserve(nv * count), nrm.reserve(nv * count), idx.reserve(ni * count), ids.reserve(nv * count);
    for (uint32_t k = 0; k < count; ++k) {
        const sg::vec3 origin(20.0f * float(k % side), 20.0f * float(k / side), 0.0f);
        const sg::vec3 size(12.0f, 12.0f, float(boxHeight(k)));
        const uint32_t base = uint32_t(pos.size());
        for (size_t v = 0; v < nv; ++v) {
            pos.push_back(origin + up[v] * size);
            nrm.push_back(un[v]);
            ids.push_back(k);
        }
        for (size_t i = 0; i < ni; ++i) idx.push_back(base + unit->index(i));
    }
    auto mesh = sg::make<sg::Mesh>();
    mesh->set(std::move(pos), std::move(nrm), std::move(idx));
    return mesh;
}

// Row k: box k's height, a name, a floor every 3 m, a use by a hash of k.
sg::ref_ptr<sg::PropertyStore> table(uint32_t count, int& index) {
    sg::PropertyTableBuilder b("building", "buildings");
    b.addScalar("height", sg::ComponentType::Float64);
    b.addString("name");
    b.addScalar("floors", sg::ComponentType::UInt16);
    b.addEnum("use", "use", {std::begin(kUses), std::end(kUses)});
    for (uint32_t k = 0; k < count; ++k)
        b.addRow(
            {sg::PropertyValue::ofNumber(boxHeight(k)), sg::PropertyValue::ofString("Building " + std::to_string(k)),
             sg::PropertyValue::ofUInt(boxHeight(k) / 3u), sg::PropertyValue::ofString(kUses[(k * 40503u >> 5) & 3u])});
    auto store = sg::make<sg::PropertyStore>();
    index = b.finish(*store);
    return store;
}

void write(sg::ref_ptr<sg::Mesh> mesh, const std::string& path) {
    auto root = sg::make<sg::Group>();
    root->addChild(sg::make<sg::Geometry>(mesh, sg::make<sg::Material>()));
    sg::saveGltf(*root, path);
}

const sg::Mesh* firstMesh(const sg::Node& n) {
    if (auto g = dynamic_cast<const sg::Geometry*>(&n)) return g->mesh();
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const sg::Mesh* m = firstMesh(*n.child(i))) return m;
    return nullptr;
}

// The loaded tile is what was written: no features for the plain one; for the other, the last box's vertices read
// the last row, whose name is the one written.
void check(const sg::GltfScene& s, bool features, uint32_t count) {
    const sg::Mesh* m = s.root ? firstMesh(*s.root) : nullptr;
    if (!m) throw std::runtime_error("sgbench load --features: a tile loaded without its mesh");
    const sg::MeshFeatures* f = m->features();
    if (!features) {
        if (f) throw std::runtime_error("sgbench load --features: the plain tile loaded with features");
        return;
    }
    if (!f || !f->store || f->sets.empty() || f->sets[0].propertyTable < 0)
        throw std::runtime_error("sgbench load --features: the tile loaded without its features or table");
    const int t = f->sets[0].propertyTable;
    const int64_t id = f->idAt(0, m->positions().size() - 1);
    // By id: saveGltf writes a schema's properties in their ids' order.
    const int nameProperty = f->store->schema.classes[size_t(f->store->tables()[size_t(t)].classIndex)].find("name");
    const sg::PropertyValue name = f->store->value(t, uint64_t(std::max<int64_t>(id, 0)), nameProperty);
    if (id != int64_t(count) - 1 || name.string != "Building " + std::to_string(count - 1))
        throw std::runtime_error("sgbench load --features: the loaded tile's last feature is not the one written");
}

double fileMb(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 ? double(st.st_size) / (1024.0 * 1024.0) : 0.0;
}

}  // namespace

int runLoadFeatures(const Args& a) {
    const long count = a.num("count", 100000), runs = a.num("runs", 5);
    if (count < 1 || count > 4000000)
        throw std::invalid_argument("sgbench load --features: --count " + std::to_string(count) +
                                    " is not in 1..4000000");
    if (runs < 1) throw std::invalid_argument("sgbench load --features: --runs must be at least 1");
    const std::string dir = a.str("dir", "/tmp");
    const std::string base = dir + "/sgbench_load_" + std::to_string(count);
    const std::string plainPath = base + "_plain.glb", featurePath = base + "_features.glb",
                      idsPath = base + "_ids.glb";

    const auto tw = Clock::now();
    size_t storeBytes = 0, triangles = 0;
    {
        std::vector<uint32_t> ids;
        const sg::ref_ptr<sg::Mesh> mesh = boxes(uint32_t(count), ids);
        triangles = mesh->triangleCount();
        write(mesh, plainPath);
        int t = -1;
        const sg::ref_ptr<sg::PropertyStore> store = table(uint32_t(count), t);
        storeBytes = store->bytes();
        auto f = sg::make<sg::MeshFeatures>();
        sg::FeatureIdSet set;
        set.label = "building";
        set.featureCount = uint32_t(count);
        set.propertyTable = t;
        set.ids = std::move(ids);
        // The same feature ids without their table: what the table alone costs.
        auto bare = sg::make<sg::MeshFeatures>();
        bare->sets.push_back(set);
        bare->sets[0].propertyTable = -1;
        mesh->setFeatures(bare);
        write(mesh, idsPath);
        f->sets.push_back(std::move(set));
        f->store = store;
        mesh->setFeatures(f);
        write(mesh, featurePath);
    }
    const double writeMs = msSince(tw);

    std::vector<double> plainMs, featureMs, idsMs, ratio, tableRatio;
    for (long r = 0; r < runs; ++r) {
        auto t0 = Clock::now();
        const sg::GltfScene plain = sg::loadGltf(plainPath);
        plainMs.push_back(msSince(t0));
        t0 = Clock::now();
        const sg::GltfScene featured = sg::loadGltf(featurePath);
        featureMs.push_back(msSince(t0));
        ratio.push_back(featureMs.back() / plainMs.back());
        t0 = Clock::now();
        const sg::GltfScene ids = sg::loadGltf(idsPath);
        idsMs.push_back(msSince(t0));
        tableRatio.push_back(featureMs.back() / idsMs.back());
        check(plain, false, uint32_t(count));
        check(featured, true, uint32_t(count));
    }
    Json j;
    j.add("command", "load").add("mode", "features").addInt("features", count).addInt("triangles", long(triangles));
    j.addInt("runs", runs).add("file_mb_plain", fileMb(plainPath)).add("file_mb_features", fileMb(featurePath));
    j.add("write_ms", writeMs).add("bytes_per_feature", double(storeBytes) / double(count));
    j.add("load_ms_median_plain", median(plainMs)).add("load_ms_median_features", median(featureMs));
    j.add("load_ms_min_plain", percentile(plainMs, 0.0)).add("load_ms_min_features", percentile(featureMs, 0.0));
    j.add("load_ratio", median(ratio));
    j.add("load_ratio_min", *std::min_element(ratio.begin(), ratio.end()));
    j.add("load_ratio_max", *std::max_element(ratio.begin(), ratio.end()));
    // Against the same tile with its feature ids but no table: the table's own cost.
    j.add("file_mb_ids", fileMb(idsPath)).add("load_ms_median_ids", median(idsMs));
    j.add("load_ratio_table", median(tableRatio));
    j.print(a);
    return 0;
}

}  // namespace bench
