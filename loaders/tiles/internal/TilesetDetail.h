// writeTileset's internals shared by its two files: the scene's units and what a tile's content holds.
#pragma once
#include "loaders/tiles/TilesetWrite.h"
#include "nodes/Group.h"
#include "sg/core/Material.h"
#include "sg/core/Math.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sg::tiles {

// No reduction: every LOD child is kept (a leaf's content, and units without distance LODs).
constexpr double kKeepAll = -1.0;

// A subtree written whole into one tile: the root's descendants where a subtree first has few enough triangles,
// descending through Groups and Transforms only (the children of an LOD or a Switch are alternatives).
struct Unit {
    const Node* node = nullptr;
    uint32_t above = 0;      // its parent frame's world matrix, in Units::matrices
    Box box;                 // world bound of what it draws, and of its LOD centres
    uint64_t triangles = 0;  // the finest child of each LOD only
    double reach = 0.0;      // largest distance at which a distance LOD's finest child shows; 0 without any
};

struct Units {
    std::vector<dmat4> matrices{dmat4(1.0)};  // one per Transform descended through; 0 is the root's frame
    std::vector<Unit> units;
};

// The units of the scene: split while a Group or Transform counts more than `unitTriangles` (one that is a feature,
// Node::setFeatures, never: its copy keeps the binding).
Units collectUnits(const Node& root, uint64_t unitTriangles);

// Triangles of `n` written with its distance LODs reduced to the children reaching beyond `d` (kKeepAll: none
// reduced), counting each LOD's finest kept child only; stops early once past `limit`.
uint64_t reducedTriangles(const Node& n, double d, uint64_t limit);

// Adds to `content` the copy of a unit, its world frame `world` above it, `toTile` mapping that world into the
// tile's frame folded into its first Transforms (so that the content holds small coordinates), and its
// distance LODs reduced at `d`.
void addUnit(Group& content, const Node& unit, const dmat4& world, const dmat4& toTile, double d);

// Places the leaves of `content` that repeat (a Geometry, or an LOD of one Geometry level, alone or under a
// Transform, below Groups and Transforms only) as Instances of one prototype per kind of leaf, children of
// `content`, and drops the nodes they leave empty; returns how many Instances it made. A leaf that is a feature
// (its Transform's or its own Node::setFeatures) gives its Instance that binding; a Group that is one stays whole.
size_t instanceRepeats(Group& content);

// A simplified proxy in a tile's frame: one triangle list per material.
struct ProxyPart {
    const Material* material = nullptr;
    std::vector<vec3> positions, normals;
    std::vector<uint32_t> indices;
};
struct Proxy {
    dvec3 centre{0.0};  // the tile's frame
    std::vector<ProxyPart> parts;
    double error = 0.0;  // against the finest levels, world units
    uint64_t triangles() const;
};

// The finest levels of a unit (each LOD's finest child, the Switch children on), into `proxy`'s frame.
// Billboards are left out (they turn to the eye: no fixed shape to merge); `skipped` counts them.
void addFinest(Proxy& proxy, const Node& unit, const dmat4& world, size_t& skipped);
// The children's proxies merged into `centre`'s frame and simplified to about `target` triangles.
Proxy simplifyMerged(const std::vector<Proxy>& children, const dvec3& centre, uint64_t target);
// A proxy as nodes (a Geometry per part).
void addProxy(Group& content, const Proxy& proxy);

// A tile as implicit tiling writes it (TilesetWriteImplicit.cpp): its quadtree position and what the explicit
// tile would say of it.
struct ImplicitTile {
    uint32_t level = 0;
    uint64_t x = 0, y = 0;
    dvec3 centre{0.0}, half{0.0};  // its box, world
    double error = 0.0;
    bool content = false;
};

// Writes the subtree files of `tiles` (one of them the root, level 0) into dir/subtrees and returns the root
// tile's JSON (its transform `rootCentre`, a box holding every tile's, implicitTiling, the content template
// tiles/{level}/{x}/{y}.glb) and in `schema` the metadata schema its subtrees' tile metadata uses. Adds the
// bytes written to `bytes`. Throws std::runtime_error naming a file it cannot write.
nlohmann::json writeImplicitTiles(const std::vector<ImplicitTile>& tiles, const dvec3& rootCentre,
                                  const std::string& dir, nlohmann::json& schema, size_t& bytes);

}  // namespace sg::tiles
