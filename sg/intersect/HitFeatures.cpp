#include "sg/intersect/HitFeatures.h"

#include "nodes/Geometry.h"

namespace sg {
namespace {

// The hit primitive's corners and their weights; false when the hit names no primitive of the mesh. A point is a
// corner of weight 1 (repeated), a segment its two ends (the second repeated with weight 0).
struct Corners {
    uint32_t v[3];
    double w[3];
    uint32_t nearest() const { return w[0] >= w[1] && w[0] >= w[2] ? v[0] : w[1] >= w[2] ? v[1] : v[2]; }
};

bool corners(const Mesh& mesh, const Hit& hit, Corners& c) {
    if (mesh.primitive() == Primitive::Points) {
        if (hit.primitive >= mesh.pointCount()) return false;
        c.v[0] = c.v[1] = c.v[2] = hit.primitive;
        c.w[0] = 1.0, c.w[1] = c.w[2] = 0.0;
        return true;
    }
    if (mesh.primitive() == Primitive::Lines) {
        if (hit.primitive >= mesh.lineCount()) return false;
        c.v[0] = mesh.index(size_t(hit.primitive) * 2);
        c.v[1] = c.v[2] = mesh.index(size_t(hit.primitive) * 2 + 1);
        c.w[0] = 1.0 - hit.u, c.w[1] = hit.u, c.w[2] = 0.0;
        return true;
    }
    if (hit.primitive >= mesh.triangleCount()) return false;
    for (int k = 0; k < 3; ++k) c.v[k] = mesh.index(size_t(hit.primitive) * 3 + size_t(k));
    c.w[0] = 1.0 - hit.u - hit.v;
    c.w[1] = hit.u;
    c.w[2] = hit.v;
    return true;
}

// The UV of set `texCoord` at the hit; false when the mesh has no such set.
bool uvAt(const Mesh& mesh, const Corners& c, int texCoord, vec2& uv) {
    const std::vector<vec2>& uvs = texCoord == 0 ? mesh.uvs() : texCoord == 1 ? mesh.uvs1() : std::vector<vec2>{};
    if (uvs.size() != mesh.positions().size()) return false;
    dvec2 sum(0.0);
    for (int k = 0; k < 3; ++k) sum += c.w[k] * dvec2(uvs[c.v[k]]);
    uv = vec2(sum);
    return true;
}

FeatureAtHit feature(const MeshFeatures& f, size_t s, int64_t id, bool instance) {
    const FeatureIdSet& set = f.sets[s];
    FeatureAtHit out;
    out.set = s;
    out.instance = instance;
    out.label = set.label;
    out.featureId = id;
    out.propertyTable = set.propertyTable;
    out.store = f.store.get();
    if (!f.store || set.propertyTable < 0 || size_t(set.propertyTable) >= f.store->tables().size()) return out;
    const PropertyTable& table = f.store->tables()[size_t(set.propertyTable)];
    out.classId = f.store->schema.classes[size_t(table.classIndex)].id;
    if (id >= 0) out.properties = f.store->row(set.propertyTable, uint64_t(id));
    return out;
}

void meshFeatures(const Mesh& mesh, const Hit& hit, HitFeatures& out) {
    const MeshFeatures& f = *mesh.features();
    Corners c;
    if (!corners(mesh, hit, c)) return;
    const uint32_t vertex = c.nearest();
    for (size_t s = 0; s < f.sets.size(); ++s) {
        int64_t id = -1;
        vec2 uv;
        if (f.sets[s].source != FeatureIdSet::Source::Texture)
            id = f.idAt(s, vertex);
        else if (uvAt(mesh, c, f.sets[s].texCoord, uv))
            id = f.idAtUv(s, uv);
        out.features.push_back(feature(f, s, id, false));
    }
    if (!f.store) return;
    const PropertyStore& store = *f.store;
    for (int t : f.propertyTextures) {
        if (t < 0 || size_t(t) >= store.propertyTextures.size()) continue;
        const PropertyTextureDef& def = store.propertyTextures[size_t(t)];
        PropertiesAtHit p{def.name, store.schema.classes[size_t(def.classIndex)].id, {}};
        const ClassDef& cls = store.schema.classes[size_t(def.classIndex)];
        for (const auto& prop : def.properties) {
            vec2 uv;
            PropertyValue v;
            if (prop.texture && uvAt(mesh, c, prop.texCoord, uv)) {
                const std::vector<uint8_t> bytes = texelChannels(*prop.texture, uv, prop.channels);
                v = store.decode(def.classIndex, prop.property, bytes.data(), bytes.size(), prop.overrides);
            }
            p.properties.emplace_back(cls.properties[size_t(prop.property)].id, std::move(v));
        }
        out.propertyTextures.push_back(std::move(p));
    }
    for (const PropertyAttributeValues& a : f.propertyAttributes) {
        if (a.propertyAttribute < 0 || size_t(a.propertyAttribute) >= store.propertyAttributes.size()) continue;
        const PropertyAttributeDef& def = store.propertyAttributes[size_t(a.propertyAttribute)];
        const ClassDef& cls = store.schema.classes[size_t(def.classIndex)];
        PropertiesAtHit p{def.name, cls.id, {}};
        for (size_t k = 0; k < def.properties.size() && k < a.columns.size(); ++k) {
            const auto& col = a.columns[k];
            const size_t at = size_t(vertex) * col.stride;
            PropertyValue v;
            if (at + col.stride <= col.bytes.size())
                v = store.decode(def.classIndex, def.properties[k].property, col.bytes.data() + at, col.stride,
                                 def.properties[k].overrides);
            p.properties.emplace_back(cls.properties[size_t(def.properties[k].property)].id, std::move(v));
        }
        out.propertyAttributes.push_back(std::move(p));
    }
}

}  // namespace

std::string propertiesText(const PropertyList& properties, const char* separator) {
    std::string s;
    for (size_t i = 0; i < properties.size(); ++i)
        s += (i ? separator : "") + properties[i].first + " " + properties[i].second.toString();
    return s;
}

HitFeatures featuresAt(const Hit& hit) {
    HitFeatures out;
    const Mesh* mesh = hit.geometry ? hit.geometry->mesh() : nullptr;
    if (mesh && mesh->features()) meshFeatures(*mesh, hit, out);
    // The nodes that are one feature each, innermost first: the instance or the part before the whole.
    for (auto n = hit.path.rbegin(); n != hit.path.rend(); ++n) {
        const MeshFeatures* f = (*n)->features();
        if (!f) continue;
        for (size_t s = 0; s < f->sets.size(); ++s)
            out.features.push_back(feature(*f, s, f->idAt(s, (*n)->featureIndex()), true));
    }
    return out;
}

}  // namespace sg
