#include "sgview/Pick.h"

#include "nodes/Geometry.h"
#include "sg/intersect/PickCone.h"
#include "sg/intersect/PickSet.h"

#include <cstdio>

namespace sgview {
namespace {

std::string quoted(const std::string& s) { return sg::PropertyValue::ofString(s).toJson(); }
std::string number(double v) { return sg::PropertyValue::ofNumber(v).toJson(); }
std::string orNull(long long v) { return v < 0 ? "null" : std::to_string(v); }

std::string propertiesJson(const sg::PropertyList& ps) {
    std::string s = "{";
    for (size_t i = 0; i < ps.size(); ++i) s += (i ? ", " : "") + quoted(ps[i].first) + ": " + ps[i].second.toJson();
    return s + "}";
}

std::string atJson(const std::vector<sg::PropertiesAtHit>& list) {
    std::string s = "[";
    for (size_t i = 0; i < list.size(); ++i)
        s += std::string(i ? ", " : "") + "{\"class\": " + quoted(list[i].classId) +
             ", \"properties\": " + propertiesJson(list[i].properties) + "}";
    return s + "]";
}

std::string featuresText(const sg::HitFeatures& f) {
    std::string s;
    for (const sg::FeatureAtHit& x : f.features) {
        s += "\n  " + std::string(x.instance ? "instance feature set " : "feature set ") + std::to_string(x.set);
        if (!x.label.empty()) s += " '" + x.label + "'";
        s += ": " + (x.featureId < 0 ? std::string("no feature") : "id " + std::to_string(x.featureId));
        if (!x.classId.empty() && x.featureId >= 0)
            s += ", class " + x.classId + ": " + sg::propertiesText(x.properties);
    }
    for (const auto& p : f.propertyTextures)
        s += "\n  property texture, class " + p.classId + ": " + sg::propertiesText(p.properties);
    for (const auto& p : f.propertyAttributes)
        s += "\n  property attribute, class " + p.classId + ": " + sg::propertiesText(p.properties);
    return s;
}

std::string nodeName(const sg::Node& n) { return n.name().empty() ? n.kindName() : n.name(); }

// What Hit::primitive counts in the hit mesh.
const char* primitiveName(const sg::Mesh* mesh) {
    if (!mesh) return "triangle";
    switch (mesh->primitive()) {
        case sg::Primitive::Points: return "point";
        case sg::Primitive::Lines: return "segment";
        case sg::Primitive::Triangles: break;
    }
    return "triangle";
}

}  // namespace

std::string featuresJson(const sg::HitFeatures& f) {
    std::string s = "\"features\": [";
    for (size_t i = 0; i < f.features.size(); ++i) {
        const sg::FeatureAtHit& x = f.features[i];
        s += std::string(i ? ", " : "") + "{\"set\": " + std::to_string(x.set) +
             (x.instance ? ", \"instance\": true" : "") +
             ", \"label\": " + (x.label.empty() ? "null" : quoted(x.label)) +
             ", \"feature_id\": " + orNull(x.featureId) + ", \"property_table\": " + orNull(x.propertyTable) +
             ", \"class\": " + (x.classId.empty() ? "null" : quoted(x.classId)) +
             ", \"properties\": " + propertiesJson(x.properties) + "}";
    }
    return s + "], \"property_textures\": " + atJson(f.propertyTextures) +
           ", \"property_attributes\": " + atJson(f.propertyAttributes);
}

Pick pickAt(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x, double y,
            sg::FeatureStyle* style) {
    // No objects registered: the path itself is the answer, down to the geometry that was hit.
    sg::QueryOptions options;
    options.style = style;
    // Points and lines within a few pixels of the pixel's ray, as a user aims at a 1-2 px point.
    const sg::PickCone cone = sg::pickCone(camera, 4.0);
    options.coneWidth = cone.coneWidth;
    options.coneSlope = cone.coneSlope;
    const sg::PickSet::Result r = sg::PickSet().pick(traversal, scene, camera, x, y, options);
    Pick p{x, y, r.hit, r.nearest, {}};
    if (p.hit) p.features = sg::featuresAt(p.nearest);
    return p;
}

std::string pickReport(const Pick& p, bool json) {
    char head[64];
    std::snprintf(head, sizeof head, "pick (%g, %g): ", p.x, p.y);
    const std::string pixel = number(p.x) + ", " + number(p.y);
    if (!p.hit) return json ? "{\"pixel\": [" + pixel + "], \"hit\": false}" : head + std::string("nothing");
    const sg::Hit& h = p.nearest;
    const sg::Mesh* mesh = h.geometry ? h.geometry->mesh() : nullptr;
    if (json) {
        std::string path = "[";
        for (size_t i = 0; i < h.path.size(); ++i) path += (i ? ", " : "") + quoted(nodeName(*h.path[i]));
        const sg::MeshSource src = mesh ? mesh->source() : sg::MeshSource{};
        return "{\"pixel\": [" + pixel + "], \"hit\": true, \"node_path\": " + path +
               "], \"source\": " + (src.file.empty() ? "null" : quoted(src.file)) +
               ", \"gltf_mesh\": " + orNull(src.gltfMesh) + ", \"gltf_primitive\": " + orNull(src.gltfPrimitive) +
               ", \"" + primitiveName(mesh) + "\": " + std::to_string(h.primitive) +
               ", \"distance\": " + number(h.distance) + ", \"point\": [" + number(h.point.x) + ", " +
               number(h.point.y) + ", " + number(h.point.z) + "], " + featuresJson(p.features) + "}";
    }
    char tail[160];
    std::snprintf(tail, sizeof tail, ", %s %u, distance %.3f, at (%.3f, %.3f, %.3f)", primitiveName(mesh),
                  unsigned(h.primitive), h.distance, h.point.x, h.point.y, h.point.z);
    return head + sg::pathString(h.path) + tail + featuresText(p.features);
}

std::string pickReport(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x,
                       double y, bool json, sg::FeatureStyle* style) {
    return pickReport(pickAt(traversal, scene, camera, x, y, style), json);
}

std::string featurePanel(const Pick& p) {
    for (const sg::FeatureAtHit& f : p.features.features) {
        if (f.featureId < 0 || f.properties.empty()) continue;
        std::string s = f.classId + " " + std::to_string(f.featureId);
        s += "\n" + sg::propertiesText(f.properties, "\n");
        return s;
    }
    return {};
}

}  // namespace sgview
