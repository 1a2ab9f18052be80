#include "map/Atlas.h"

#include "loaders/gltf/Gltf.h"
#include "map/RegionFeatures.h"
#include "map/data/MapProjection.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/build/LodGenerator.h"

#include <algorithm>
#include <complex>
#include <filesystem>
#include <stdexcept>

namespace sgmap {

using namespace sg;

namespace {

std::string str(const GltfProperties& p, const std::string& key) {
    const auto it = p.strings.find(key);
    return it == p.strings.end() ? std::string() : it->second;
}

// The similarity (scale, turn, shift in the plane) that best carries the U.S. level's Albers plane onto the world
// level's Equal Earth plane over the conterminous states (least squares on a grid of points): the two equal-area
// projections agree there to about 1%, the insets (Alaska, Hawaii) do not: they stay where a U.S. map draws them.
dmat4 usOntoWorld() {
    const MapProjection world = MapProjection::world(), us = MapProjection::usState("20");
    std::vector<std::complex<double>> a, b;
    for (double lon = -122.0; lon <= -70.0; lon += 4.0)
        for (double lat = 28.0; lat <= 48.0; lat += 4.0) {
            const glm::dvec2 pw = world.project(lon, lat), pu = us.project(lon, lat);
            a.emplace_back(pw.x, pw.y);
            b.emplace_back(pu.x, pu.y);
        }
    std::complex<double> ca, cb;
    for (size_t i = 0; i < a.size(); ++i) ca += a[i], cb += b[i];
    ca /= double(a.size());
    cb /= double(a.size());
    std::complex<double> num;
    double den = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        num += std::conj(b[i] - cb) * (a[i] - ca);
        den += std::norm(b[i] - cb);
    }
    const std::complex<double> z = num / den, t = ca - z * cb;  // a = z b + t
    const double s = std::abs(z);
    dmat4 m(1.0);
    m[0] = dvec4(z.real(), z.imag(), 0.0, 0.0);
    m[1] = dvec4(-z.imag(), z.real(), 0.0, 0.0);
    m[2] = dvec4(0.0, 0.0, s, 0.0);
    m[3] = dvec4(t.real(), t.imag(), 0.0, 1.0);
    return m;
}

// The child level's plane fitted by uniform scale into the region's bounds (the generated map, which has no
// projection to go by).
dmat4 boundsFit(const Box& child, const Box& region) {
    const double s = std::min((region.max.x - region.min.x) / std::max(1e-9, child.max.x - child.min.x),
                              (region.max.y - region.min.y) / std::max(1e-9, child.max.y - child.min.y));
    const dvec3 c = child.center(), r = region.center();
    dmat4 m = glm::scale(dmat4(1.0), dvec3(s));
    m[3] = dvec4(r.x - s * c.x, r.y - s * c.y, 0.0, 1.0);
    return m;
}

// The bounds of the mesh's largest connected piece by the area of its upward faces (union-find over the
// triangles' vertices).
Box largestPiece(const Mesh& m) {
    const auto& p = m.positions();
    std::vector<uint32_t> up(p.size());
    for (uint32_t i = 0; i < up.size(); ++i) up[i] = i;
    auto find = [&](uint32_t v) {
        while (up[v] != v) v = up[v] = up[up[v]];
        return v;
    };
    const size_t n = m.indexCount() / 3;
    for (size_t t = 0; t < n; ++t) {
        const uint32_t a = find(m.index(3 * t)), b = find(m.index(3 * t + 1)), c = find(m.index(3 * t + 2));
        up[b] = a;
        up[find(c)] = a;
    }
    std::unordered_map<uint32_t, double> area;
    for (size_t t = 0; t < n; ++t) {
        const dvec3 a(p[m.index(3 * t)]), b(p[m.index(3 * t + 1)]), c(p[m.index(3 * t + 2)]);
        area[find(m.index(3 * t))] += std::max(0.0, glm::cross(b - a, c - a).z);
    }
    uint32_t best = 0;
    double most = -1.0;
    for (const auto& [root, a] : area)
        if (a > most) most = a, best = root;
    Box box;
    for (size_t v = 0; v < p.size(); ++v)
        if (find(uint32_t(v)) == best) box.expand(dvec3(p[v]));
    return box;
}

// The regions' meshes as one, each region's vertices coloured by its material.
void mergeLevel(Level& level, Group& root) {
    std::vector<vec3> pos, nrm;
    std::vector<vec4> col;
    std::vector<uint32_t> idx;
    for (Region& r : level.regions) {
        Geometry& g = *r.geometries[0];
        const Mesh& m = *g.mesh();
        const vec4 c = g.material() ? g.material()->baseColor : vec4(1.0f);
        const size_t n = m.positions().size();
        r.firstVertex = uint32_t(pos.size());
        r.vertexCount = uint32_t(n);
        pos.insert(pos.end(), m.positions().begin(), m.positions().end());
        for (size_t v = 0; v < n; ++v) {
            nrm.push_back(m.normals().size() == n ? m.normals()[v] : vec3(0.0f, 0.0f, 1.0f));
            col.push_back(m.colors().size() == n ? c * m.colors()[v] : c);
        }
        for (size_t i = 0; i < m.indexCount(); ++i) idx.push_back(r.firstVertex + m.index(i));
        g.setNodeMask(kPickable);  // picked, not drawn
    }
    level.mergedColors = col;
    auto mesh = make<Mesh>();
    mesh->set(std::move(pos), std::move(nrm), std::move(idx), {}, std::move(col));
    auto geom = make<Geometry>(mesh, make<Material>(vec4(1.0f)));
    geom->setName(level.name + " " + level.parent + " as one mesh");
    geom->setNodeMask(~(kPickable | kCollidable));  // drawn, not picked
    root.addChild(geom);
    level.merged = geom.get();
}

void replace(Node* old, ref_ptr<Node> with) {
    auto* parent = static_cast<Group*>(old->parent(0));
    const size_t i = parent->indexOf(old);
    ref_ptr<Node> keep(old);
    parent->removeChild(i);
    parent->insertChild(i, std::move(with));
}

}  // namespace

const vec4 Atlas::kHighlight{1.0f, 0.85f, 0.2f, 1.0f};

int Level::findId(const std::string& id) const {
    for (size_t i = 0; i < regions.size(); ++i)
        if (regions[i].id == id) return int(i);
    return -1;
}

Atlas::Atlas(const std::string& dataDir, AtlasSettings settings) : dir_(dataDir), settings_(settings) {
    std::shared_ptr<Level> world = readLevel((std::filesystem::path(dir_) / "world.glb").string(), nullptr);
    generated_ = world->projection.empty();
    root_ = make<Group>();
    root_->setName("map");
    root_->addChild(world->root);
    chain_.push_back(world);
    for (const Region& r : world->regions) picks_.add(r.node);
    scene_ = std::make_unique<Scene>(root_);
    scene_->update();
    pager_ = std::make_unique<Pager>(
        *scene_, [this](const std::string& file) { return load(file); }, settings_.pager);
}

Atlas::~Atlas() { pager_.reset(); }

std::shared_ptr<Level> Atlas::readLevel(const std::string& file, const Request* parent) const {
    GltfScene g = loadGltf(file);
    auto level = std::make_shared<Level>();
    level->name = str(g.sceneProperties, "level");
    level->parent = str(g.sceneProperties, "parent");
    level->projection = str(g.sceneProperties, "projection");
    if (level->name.empty()) throw LoadError(file, "scenes[0].extras", "not a map level (no `level`)");
    Box all;
    for (const auto& [node, p] : g.properties) {
        if (node->kind() != NodeKind::Geometry || str(p, "kind").empty()) continue;
        auto* geom = static_cast<Geometry*>(const_cast<Node*>(node));
        Region r;
        r.id = str(p, "id");
        r.name = str(p, "name");
        r.kind = str(p, "kind");
        r.child = str(p, "child");
        if (const auto it = p.numbers.find("area_km2"); it != p.numbers.end()) r.areaKm2 = it->second;
        r.node = geom;
        r.geometries = {geom};
        for (const vec3& v : geom->mesh()->positions()) r.box.expand(dvec3(v));
        all.expand(r.box);
        level->triangles += geom->mesh()->indexCount() / 3;
        level->regions.push_back(std::move(r));
    }
    if (level->regions.empty()) throw LoadError(file, "nodes", "no regions (nodes with a `kind`)");
    // By id: the properties come in no set order, and region indices must not change between runs.
    std::sort(level->regions.begin(), level->regions.end(),
              [](const Region& a, const Region& b) { return a.id != b.id ? a.id < b.id : a.name < b.name; });

    const bool lod = level->triangles > settings_.lodAbove;
    for (Region& r : level->regions) {
        Geometry* geom = r.geometries[0];
        if (lod && geom->mesh()->indexCount() >= 3 * 64) {
            ref_ptr<LOD> l = makeLod(ref_ptr<Mesh>(geom->mesh()), ref_ptr<Material>(geom->material()), {0.25f, 0.05f},
                                     settings_.lodPixelError, settings_.pixelsPerRadian);
            l->setName(r.name);
            replace(geom, l);
            r.node = l.get();
            r.geometries.clear();
            for (size_t i = 0; i < l->numChildren(); ++i) r.geometries.push_back(static_cast<Geometry*>(l->child(i)));
        }
        if (!r.child.empty()) {
            auto p = make<PagedLOD>();
            p->setName(r.name);
            p->setTrigger(PagedLOD::Trigger::Command);
            p->setFile((std::filesystem::path(dir_) / r.child).string());
            const ref_ptr<Node> coarse(r.node);
            replace(r.node, p);
            p->addChild(coarse);
            r.node = p.get();
            r.paged = p.get();
        }
    }
    for (size_t i = 0; i < level->regions.size(); ++i) level->byNode[level->regions[i].node] = i;
    bindRegionFeatures(*level);
    const bool plain = std::none_of(level->regions.begin(), level->regions.end(),
                                    [](const Region& r) { return r.paged || r.geometries.size() != 1; });
    if (plain) mergeLevel(*level, static_cast<Group&>(*g.root));

    if (!parent) {
        level->root = g.root;
    } else {
        dmat4 fit(1.0);  // a state's counties are in the U.S. level's plane
        if (parent->parentName == "world")
            fit = !parent->parentProjection.empty() && !level->projection.empty() ? usOntoWorld()
                                                                                  : boundsFit(all, parent->regionBox);
        auto t = make<Transform>(fit);
        t->setName(level->name + " " + level->parent);
        t->addChild(g.root);
        level->root = t;
        level->toScene = parent->parentToScene * fit;
    }
    level->bytes = pageBytes(level->root.get());
    return level;
}

ref_ptr<Node> Atlas::load(const std::string& file) {
    Request req;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = requests_.find(file);
        if (it == requests_.end()) throw std::runtime_error(file + ": not requested by the map");
        req = it->second;
    }
    std::shared_ptr<Level> level = readLevel(file, &req);
    // The nodes go to the pager alone (the level keeps plain pointers until attached): were the level dropped
    // on this thread while the pager frees its root on the other, the two would count references at once.
    ref_ptr<Node> root = std::move(level->root);
    level->read = root.get();
    std::lock_guard<std::mutex> lock(mutex_);
    if (const auto it = requests_.find(file); it != requests_.end() && it->second.id == req.id) read_[file] = level;
    return root;
}

std::string Atlas::enter(size_t index) {
    const Level& cur = level();
    if (index >= cur.regions.size()) return "no region " + std::to_string(index);
    const Region& r = cur.regions[index];
    if (entering_ >= 0) return "already entering " + cur.regions[size_t(entering_)].name;
    if (!r.paged) return r.name + " (" + r.kind + " " + r.id + ") has no level below it";
    {
        std::lock_guard<std::mutex> lock(mutex_);
        requests_[r.paged->file()] = Request{cur.name, cur.projection, r.box, cur.toScene, nextRequest_++};
        read_.erase(r.paged->file());
    }
    pager_->load(*r.paged);
    entering_ = int(index);
    enterStart_ = std::chrono::steady_clock::now();
    return {};
}

Atlas::Step Atlas::update(const FrameInfo& frame) {
    pager_->update(frame);
    const Step s = step();
    scene_->update(frame);
    return s;
}

Atlas::Step Atlas::step() {
    Step step;
    if (entering_ >= 0) {
        const size_t index = size_t(entering_);
        PagedLOD& p = *level().regions[index].paged;
        if (p.state() == PagedLOD::State::Loaded) {
            std::shared_ptr<Level> next;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                const auto it = read_.find(p.file());
                if (it != read_.end() && it->second->read == p.detail()) next = it->second;
                read_.erase(p.file());
                requests_.erase(p.file());
            }
            entering_ = -1;
            if (!next) {
                step.error = p.file() + ": attached without its regions";
                pager_->release(p);
            } else {
                next->root = ref_ptr<Node>(p.detail());
                highlight(-1);
                if (level().name == "world") showSiblings(level(), index, false);
                chain_.push_back(next);
                picks_.clear();
                for (const Region& r : next->regions) picks_.add(r.node);
                step.entered = true;
            }
        } else if (p.state() == PagedLOD::State::Failed || p.state() == PagedLOD::State::Unloaded) {
            step.error = p.state() == PagedLOD::State::Failed ? p.error() : p.file() + ": the request was dropped";
            entering_ = -1;
            std::lock_guard<std::mutex> lock(mutex_);
            requests_.erase(p.file());
            read_.erase(p.file());
        }
        if (!step.error.empty()) lastError_ = step.error;
    }
    return step;
}

std::string Atlas::back() {
    if (entering_ >= 0) {  // the load in flight is dropped (or its detail freed when it has arrived)
        PagedLOD& p = *level().regions[size_t(entering_)].paged;
        const std::string name = level().regions[size_t(entering_)].name;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            requests_.erase(p.file());
            read_.erase(p.file());
        }
        pager_->release(p);
        entering_ = -1;
        return "stopped entering " + name;
    }
    if (chain_.size() < 2) return "at the world level: there is no level above";
    highlight(-1);
    const std::shared_ptr<Level> left = chain_.back();
    chain_.pop_back();
    const Level& parent = level();
    size_t index = 0;
    while (index < parent.regions.size() &&
           !(parent.regions[index].paged && parent.regions[index].paged->detail() == left->root.get()))
        ++index;
    if (index == parent.regions.size()) throw std::logic_error("Atlas::back(): the level left is not attached");
    pager_->release(*parent.regions[index].paged);
    if (parent.name == "world") showSiblings(parent, index, true);
    picks_.clear();
    for (const Region& r : parent.regions) picks_.add(r.node);
    intersect_.bvhCache().clear();  // it holds the meshes of the level left
    scene_->update(scene_->frame());
    return {};
}

void Atlas::showSiblings(const Level& parent, size_t region, bool show) {
    for (size_t i = 0; i < parent.regions.size(); ++i)
        if (i != region) parent.regions[i].node->setNodeMask(show ? ~0u : 0u);
}

int Atlas::pick(const Ray& ray, const QueryOptions& options, Hit* out) {
    scene_->update(scene_->frame());  // a highlight or a level changed since: one flag check when nothing did
    Hit h;
    if (!intersect_.intersect(*scene_, ray, options, h)) return -1;
    if (out) *out = h;
    const Node* n = picks_.resolve(h.path);
    const auto it = n ? level().byNode.find(n) : level().byNode.end();
    return it == level().byNode.end() ? -1 : int(it->second);
}

int Atlas::pickPixel(const Camera& camera, double x, double y) {
    scene_->update(scene_->frame());  // a highlight or a level changed since: one flag check when nothing did
    const PickSet::Result r = picks_.pick(intersect_, *scene_, camera, x, y);
    const auto it = r.object ? level().byNode.find(r.object) : level().byNode.end();
    return it == level().byNode.end() ? -1 : int(it->second);
}

int Atlas::pickGeo(double lon, double lat) {
    const dvec3 p = geoToScene(lon, lat);
    // From above the tallest prism (80 km) to below the plane.
    const Ray ray{p + dvec3(0.0, 0.0, 1000.0), dvec3(0.0, 0.0, -1.0), 2000.0};
    QueryOptions o;
    o.lod = LodChoice::Highest;
    return pick(ray, o);
}

dvec3 Atlas::geoToScene(double lon, double lat) const {
    if (generated_) return dvec3(lon, lat, 0.0);
    const Level& l = level();
    const glm::dvec2 p =
        l.name == "world" ? MapProjection::world().project(lon, lat) : MapProjection::usAt(lon, lat).project(lon, lat);
    return dvec3(l.toScene * dvec4(p, 0.0, 1.0));
}

Box Atlas::sceneBox(size_t index, bool main) {
    Level& l = *chain_.back();
    Region& r = l.regions.at(index);
    if (main && r.mainBox.empty()) r.mainBox = largestPiece(*r.geometries[0]->mesh());
    const Box& b = main && !r.mainBox.empty() ? r.mainBox : r.box;
    Box out;
    for (int c = 0; c < 8; ++c)
        out.expand(dvec3(l.toScene *
                         dvec4(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z, 1.0)));
    return out;
}

void Atlas::highlight(int index) {
    if (Level& l = *chain_.back(); l.merged) {  // the region's vertices of the level's mesh recoloured
        highlighted_ = index >= 0 && size_t(index) < l.regions.size() ? index : -1;
        std::vector<vec4> col = l.mergedColors;
        if (highlighted_ >= 0) {
            const Region& r = l.regions[size_t(index)];
            std::fill(col.begin() + r.firstVertex, col.begin() + r.firstVertex + r.vertexCount, kHighlight);
        }
        const Mesh& m = *l.merged->mesh();
        std::vector<uint32_t> idx(m.indexCount());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
        auto mesh = make<Mesh>();  // a new mesh, since a renderer keeps its copy of one it has drawn
        mesh->set(m.positions(), m.normals(), std::move(idx), {}, std::move(col));
        l.merged->setMesh(mesh);
        return;
    }
    if (highlighted_ >= 0) {
        Region& r = chain_.back()->regions[size_t(highlighted_)];
        for (size_t i = 0; i < r.geometries.size() && i < saved_.size(); ++i) r.geometries[i]->setMaterial(saved_[i]);
    }
    saved_.clear();
    highlighted_ = -1;
    if (index < 0 || size_t(index) >= level().regions.size()) return;
    highlighted_ = index;
    auto lit = make<Material>(kHighlight);
    for (Geometry* g : chain_.back()->regions[size_t(index)].geometries) {
        saved_.push_back(ref_ptr<Material>(g->material()));
        g->setMaterial(lit);
    }
}

size_t Atlas::bytesLoaded() const {
    size_t b = 0;
    for (const auto& l : chain_) b += l->bytes;
    return b;
}

}  // namespace sgmap
