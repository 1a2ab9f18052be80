// What a hit says about the features it struck: for each feature ID set of the hit mesh (and of the nodes on its path
// that are one feature each: an instance, a building) the feature's id and its properties, and the property textures
// and attributes evaluated at the hit.
#pragma once
#include "sg/core/Properties.h"
#include "sg/intersect/Intersect.h"

#include <string>
#include <utility>
#include <vector>

namespace sg {

using PropertyList = std::vector<std::pair<std::string, PropertyValue>>;  // by the property's id in the schema

struct FeatureAtHit {
    size_t set = 0;         // the set's index in the mesh's MeshFeatures (or the node's)
    bool instance = false;  // a set of a node on the path (Node::setFeatures: EXT_instance_features, an i3dm)
    std::string label;
    int64_t featureId = -1;  // -1: no feature (the set's null id, or nothing readable at the hit)
    int propertyTable = -1;
    std::string classId;  // the table's class; empty without a table
    PropertyList properties;
    const PropertyStore* store = nullptr;  // the set's (FeatureStyle::setHighlight names a feature by it)
};

struct PropertiesAtHit {
    std::string name, classId;
    PropertyList properties;
};

struct HitFeatures {
    std::vector<FeatureAtHit> features;
    std::vector<PropertiesAtHit> propertyTextures, propertyAttributes;
    bool empty() const { return features.empty() && propertyTextures.empty() && propertyAttributes.empty(); }
};

// Properties as a viewer prints them: "id value" each (PropertyValue::toString), joined by `separator`.
std::string propertiesText(const PropertyList& properties, const char* separator = ", ");

// Feature ids at the hit: an attribute's (or the implicit vertex index) at the vertex of the hit triangle nearest
// the hit point (all three agree on a feature's own triangles), a hit point's own vertex, a hit segment's nearer end; a
// texture's at the nearest texel of the hit's interpolated UV; a node's (Node::setFeatures) for each node on the path
// that has them, innermost first. Property attributes likewise at the nearest vertex.
HitFeatures featuresAt(const Hit& hit);

}  // namespace sg
