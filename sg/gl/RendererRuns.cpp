// Renderer: the draw list into runs of equal state, each one instanced draw.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/BackFaces.h"
#include "sg/gl/internal/Shaders.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

// The centre of what an item draws, relative to the eye: a skinned pose's box is in world coordinates, and the item's
// matrix puts its anchor where it stands from the eye; other poses' boxes are in the item's frame.
vec3 drawnCenter(const DrawItem& it, const Pose* pose) {
    if (pose && pose->skinned()) return it.model * vec4(vec3(pose->box.center() - pose->anchor), 1.0f);
    const Mesh& m = pose ? pose->drawn(*it.mesh) : *it.mesh;
    return it.model * vec4(vec3(m.box().center()), 1.0f);
}

}  // namespace

// Dissolving items are few: a dense copy of DrawList::fades only in frames that have them.
void Renderer::indexFades(const DrawList& list) {
    fades_.clear();
    if (list.fades.empty()) return;
    fades_.assign(list.items.size(), 1.0f);
    for (const auto& [i, f] : list.fades)
        if (i < fades_.size() && f > -1.0f && f < 1.0f) fades_[i] = f;
}

void Renderer::indexFeatures(const DrawList& list) {
    itemFeatureColors_.clear();
    if (list.features.empty() || !featureStyle_) return;
    // Alpha -1: not yet given by a range (the first range holding an item, the innermost node's, gives it).
    itemFeatureColors_.assign(list.items.size(), vec4(1.0f, 1.0f, 1.0f, -1.0f));
    // Ranges of one table come one after another: its colours are asked for once per run, not per range.
    const PropertyStore* store = nullptr;
    int table = -1;
    std::shared_ptr<const FeatureStyle::Colors> colors;
    for (const DrawList::Feature& f : list.features) {
        if (!f.features || f.features->sets.empty()) continue;
        vec4 color(1.0f);
        const int t = f.features->sets[0].propertyTable;
        if (f.features->store && t >= 0) {
            if (f.features->store.get() != store || t != table) {
                store = f.features->store.get();
                table = t;
                colors = featureStyle_->colors(*store, table);
            }
            const int64_t id = f.features->idAt(0, f.index);
            if (id >= 0 && size_t(id) * 4 + 3 < colors->rgba.size()) {
                const uint8_t* px = &colors->rgba[size_t(id) * 4];
                color = vec4(px[0], px[1], px[2], px[3]) / 255.0f;
            }
        }
        for (size_t k = f.first; k < f.end && k < itemFeatureColors_.size(); ++k)
            if (itemFeatureColors_[k].a < 0.0f) itemFeatureColors_[k] = color;
    }
    for (vec4& c : itemFeatureColors_)
        if (c.a < 0.0f) c = vec4(1.0f);
}

// Like fades: a dense copy of DrawList::parts only in frames that draw items in part, each part checked.
void Renderer::indexParts(const DrawList& list) {
    parts_.clear();
    if (list.parts.empty()) return;
    parts_.assign(list.items.size(), kWhole);
    for (size_t p = 0; p < list.parts.size(); ++p) {
        const DrawList::Part& part = list.parts[p];
        const Mesh* m = part.item < list.items.size() ? list.items[part.item].mesh : nullptr;
        // A posed item is drawn whole: the ranges are the unposed mesh's triangles that reach the screen.
        if (part.item < poses_.size() && poses_[part.item]) continue;
        // Index ranges are triangles' (the cull cuts triangle meshes only): points and lines are drawn whole.
        if (m && m->primitive() != Primitive::Triangles) continue;
        bool ok = m && uint64_t(part.first) + part.count <= list.ranges.size();
        for (uint32_t r = 0; ok && r < part.count; ++r) {
            const IndexRange& ir = list.ranges[size_t(part.first) + r];
            ok = uint64_t(ir.first) + ir.count <= m->indexCount();
        }
        if (!ok)
            throw std::out_of_range("Renderer::draw(): parts[" + std::to_string(p) + "] (item " +
                                    std::to_string(part.item) + ", ranges " + std::to_string(part.first) + " + " +
                                    std::to_string(part.count) + ") is past the items, the " +
                                    std::to_string(list.ranges.size()) + " ranges or its mesh's indices");
        parts_[part.item] = uint32_t(p);
    }
}

// Runs of equal (mesh, material) pointers in draw order, split where the back faces' culling changes, a skinned item
// alone (its joints are bound per draw); blended items (Material::blend) after all others, farthest first by the
// centre of their bound along the view. Every matrix of the frame goes in one buffer.
void Renderer::buildRuns(const DrawList& list, const Camera& camera) {
    const double reach = backFaceCulling_ ? nearPlaneReach(camera) : -1.0;
    const size_t n = list.order.empty() ? list.items.size() : list.order.size();
    items_.clear();
    runs_.clear();
    blended_.clear();
    indexFades(list);
    indexPoses(list);  // before the parts, which posed items do without
    indexParts(list);
    indexFeatures(list);
    const vec3 view(camera.viewDirection());
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = list.order.empty() ? uint32_t(k) : list.order[k];
        if (i >= list.items.size())
            throw std::out_of_range("Renderer::draw(): order[" + std::to_string(k) + "] = " + std::to_string(i) +
                                    " is past the " + std::to_string(list.items.size()) + " items");
        const DrawItem& it = list.items[i];
        if (!it.mesh || it.mesh->primitiveCount() == 0) continue;
        if (!itemFeatureColors_.empty() && itemFeatureColors_[i].a == 0.0f) continue;  // a hidden feature
        if (it.material && it.material->blend) {
            const float depth = glm::dot(view, drawnCenter(it, poses_.empty() ? nullptr : poses_[i]));
            blended_.push_back({std::isfinite(depth) ? depth : 0.0f, i});
            continue;
        }
        addItem(list, i, reach);
    }
    std::stable_sort(blended_.begin(), blended_.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [depth, i] : blended_) addItem(list, i, reach);
}

void Renderer::addItem(const DrawList& list, uint32_t i, double reach) {
    const DrawItem& it = list.items[i];
    const float fade = fades_.empty() ? 1.0f : fades_[i];
    const uint32_t part = parts_.empty() ? kWhole : parts_[i];
    const Material* mat = it.material;
    const Pose* pose = poses_.empty() ? nullptr : poses_[i];
    const Mesh* mesh = drawnMesh(it, pose);
    const Pose* skin = gpuSkinned(pose, *mesh) ? pose : nullptr;
    // A single-sided material's back faces are never drawn (glTF: "back-face culling must be enabled"); a mirroring
    // matrix turns which winding is in front. Points and lines have no back: their quads (llvmpipe's, or the wide
    // lines' geometry stage) must not be culled by the way they happen to wind. A posed item's back faces are not
    // proved hidden: the proof is about the unposed mesh (a skin may even fold it through itself).
    const bool single = mat && !mat->doubleSided && mesh->primitive() == Primitive::Triangles;
    const bool mirrored = single && glm::determinant(glm::mat3(it.model)) < 0.0f;
    const bool cullBack = single || (!pose && fade == 1.0f && (part == kWhole || list.parts[part].coversScreen) &&
                                     backFacesHidden(it, mat, reach));
    if (runs_.empty() || runs_.back().mesh != mesh || runs_.back().material != mat || runs_.back().fade != fade ||
        part != kWhole || runs_.back().part != kWhole || runs_.back().cullBack != cullBack ||
        runs_.back().mirrored != mirrored || skin || runs_.back().skin) {
        runs_.push_back(Run{mesh,
                            mat,
                            uint32_t(items_.size()),
                            0,
                            fade,
                            part,
                            cullBack,
                            mirrored,
                            mat && mat->blend,
                            nullptr,
                            0,
                            {},
                            nullptr,
                            {}});
        runs_.back().skin = skin;
    }
    runs_.back().count++;
    vec4 base = mat ? mat->baseColor : vec4(1.0f);
    if (!itemFeatureColors_.empty()) base *= vec4(vec3(itemFeatureColors_[i]), 1.0f);  // its feature's colour
    items_.push_back(ItemAttributes{it.matrix(), base});
}

}  // namespace sg
