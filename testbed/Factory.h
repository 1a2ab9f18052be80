// The `factory` scene: a procedural factory site after the Performer walkthrough paper (hills, roads, a
// stream, workshops with instanced machines behind switches), as docs/scenes.md describes it.
#pragma once
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/build/LevelReshade.h"
#include "sg/core/Camera.h"
#include "sg/core/Features.h"
#include "sg/core/Mesh.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace scenes {

struct FactoryParams {
    uint32_t seed = 1996;          // hills, trees and car placement
    double siteSize = 800.0;       // side of the square terrain, metres, centred on the origin
    int terrainCells = 248;        // height-field cells per side (3.2 m each)
    int terrainTiles = 8;          // LOD pieces per side (must divide terrainCells; 100 m each)
    int machinesPerWorkshop = 17;  // Instances of the machine group in each workshop
    int trees = 140;               // axial billboards around the yard (plus a row along its north edge)
    int cars = 24;                 // Instances of the car model in the car park (at most 64, the bays)
    double pixelError = 1.0;       // coarse models are shown where their error projects to at most this
    double fadeFraction = 0.1;     // fade band width, as a share of the distance where the level switches
};

// How a coarse level of a building model takes its colours from the detailed level (sg::generateLevels with
// LevelShading::reshade).
using FactoryColorShare = sg::LevelColorShare;

// One of the 11 buildings: its placement, its levelled model and the occluder standing for it.
struct FactoryBuilding {
    std::string kind;  // "workshop", "auxiliary", "technology" or "office"
    sg::ref_ptr<sg::Transform> place;
    sg::ref_ptr<sg::LOD> lod;                     // child 0 the detailed model, then the simplified ones
    sg::ref_ptr<sg::Geometry> roof;               // the roofing over the model's slab, beside the LOD (its own texture)
    sg::ref_ptr<sg::Occluder> occluder;           // world box, under the root's "occluders" group (not switched)
    sg::Box box;                                  // world box of the walls and roof (what an eye is "inside")
    std::vector<FactoryColorShare> coarseColors;  // of LOD child i >= 1 at i - 1 (see shareBuildingColors)
};

struct FactoryWorkshop {
    int building = 0;                  // index into Factory::buildings
    sg::ref_ptr<sg::Switch> interior;  // machines, conveyors, pillars, inner walls; off by default
    sg::ref_ptr<sg::Group> interiorGroup;
};

struct Factory {
    sg::ref_ptr<sg::Group> root;
    // Terrain, roads, stream, bridge, chimney, trees, cars and every building's exterior: an application
    // turns it off while the eye is inside a workshop (a closed building hides all of it).
    sg::ref_ptr<sg::Switch> outside;
    std::vector<FactoryBuilding> buildings;  // workshops first (4), then auxiliary (5), technology, office
    std::vector<FactoryWorkshop> workshops;
    sg::ref_ptr<sg::LOD> machine;       // the machine group: the prototype every machine Instance places
    sg::ref_ptr<sg::Mesh> machineMesh;  // its detailed level
    // One LOD per tile: child 0 the full grid, then coarser grids stitched to the same full-resolution
    // border (so no cracks between tiles at different levels), each shown where its error is below a pixel.
    sg::ref_ptr<sg::Group> terrain;
    // Ground height at (x, y): the terrain mesh's own surface (the height field interpolated over its
    // triangles), the ground level outside the site. For walking: eye height = terrainHeight + 1.7.
    std::function<double(double, double)> terrainHeight;
    uint64_t storedTriangles = 0;  // every distinct mesh once, at its finest level (what memory holds)
    uint64_t drawnTriangles = 0;   // every placement, all switches on, finest levels (what a full view draws)
    int machines = 0, trees = 0, cars = 0;
    // The feature ID sets the buildings' and machines' nodes name (Node::setFeatures), over one property store:
    // class `building` (name, kind), row b for buildings[b], bound to its Transform and, for a workshop, its
    // interior; class `machine` (name, kind, line), one row per machine Instance in workshop order.
    sg::ref_ptr<sg::MeshFeatures> buildingFeatures, machineFeatures;
};

// Throws std::invalid_argument naming the function and the value for a site size that is not finite or
// below 600 m (the yard and its ring of trees), terrain cells not a positive multiple of the tiles, a
// negative count, more than 64 cars or 21 machines per workshop (three rows of 7), a pixel error that is
// not positive and finite, or a fade fraction outside [0, 1).
Factory buildFactory(const FactoryParams& params = {});

// Gives the coarse levels of every terrain tile colours from its finest level, after those have changed (baked
// light): a border vertex, shared with the neighbours, takes the finest colour at its point; an inner vertex
// the mean of the finest colours within half its level's spacing (a coarse level stands for that area).
// Each coarse level's error (LOD::setError, the LOD budget's measure of accuracy) becomes at least the error
// of its light: the worst colour difference from the finest level times the level's spacing (a shadow on a
// flat yard is lost by a coarse level whose geometry is exact). Throws std::invalid_argument naming the function for a
// terrain that buildFactory() did not make.
void shareTerrainColors(Factory& f);

// Gives the coarse levels of every building model colours from its detailed level, after those have changed
// (baked light), by the building's coarseColors, which buildFactory() makes: each coarse vertex takes the
// detailed surface's colour sampled over its triangles, at the nearest point facing within 45 degrees of the
// vertex's normal, weighted as the coarse surface interpolates it, so that a coarse face's mean colour is the
// detailed surface's under it. Light baked from the coarse levels' own vertices would be sampled on simplified
// faces behind the detailed walls, in the dark. Throws std::invalid_argument naming the function for a building
// whose coarseColors do not match its levels.
void shareBuildingColors(Factory& f);

// Machine k (0-based, in placing order) of workshop w (0-based): "machine 2.05" for k = 4 of w = 1.
std::string factoryMachineName(int workshop, int k);

// The workshop whose box holds `eye`, or -1.
int factoryWorkshopAt(const Factory& f, const sg::dvec3& eye);
// What an application does as the eye moves: inside workshop k (k >= 0) the outside is off and only that
// workshop's interior is on; with k = -1 the defaults are back (outside on, every interior off).
void setFactoryEye(Factory& f, int workshop);

constexpr int kFactoryOrbitFrames = 120;
// Orbit around the site at 300 m radius, 90 m up, looking at the yard; viewport 1280x720, fov 60, near 1,
// far 3000; frame f of 120.
sg::Camera factoryOrbitCamera(int frame, int width = 1280, int height = 720);
// Standing in workshop k's west end at eye height, looking down its length (+x).
sg::Camera factoryWorkshopCamera(const Factory& f, int workshop, int width = 1280, int height = 720);

}  // namespace scenes
