// sgbench pvs: from-region visibility tables (sg/build/PvsBuilder.h) on city's street path and office's walk
// (docs/scenes.md): per cell size and per number of occluders per cell, the share of the scene hidden from
// the path's frames (mean over the frames inside a cell) and the time to build the table.
#include "sg/build/PvsBuilder.h"
#include "sg/scene/Scene.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <cmath>
#include <stdexcept>

namespace bench {

sg::PvsBuilder::Options pvsPathOptions(bool city, int n, const std::vector<sg::Camera>& cams) {
    sg::PvsBuilder::Options o;
    if (city) {  // the street the path walks (between buildings 4 m either side), at eye height
        const double x = 20.0 * std::floor(n / 2.0);
        o.region = sg::Box{sg::dvec3(x - 2, 0, 1.2), sg::dvec3(x + 2, 20.0 * n, 2.2)};
    } else {  // the row of rooms the walk crosses, through their doors, at eye height
        const double y = 6.0 * std::floor(n / 2.0) + 3.0;
        o.region = sg::Box{sg::dvec3(0.5, y - 0.4, 1.2), sg::dvec3(6.0 * n - 0.5, y + 0.4, 2.0)};
    }
    o.minNear = o.maxNear = cams.empty() ? 0.1 : cams[0].nearDistance();
    for (const sg::Camera& c : cams) {
        o.minNear = std::min(o.minNear, c.nearDistance());
        o.only.push_back(c.eye());
    }
    o.maxNear = std::max(1.0, o.minNear);
    return o;
}

namespace {
// Entries and triangles (every LOD level counted) hidden from the cell holding `eye`.
void hiddenShare(const sg::FlatImage& img, const sg::PvsTable& t, const sg::dvec3& eye, double& entries, double& tris) {
    entries = tris = 0.0;
    const uint64_t* h = t.hiddenFor(eye);
    if (!h) return;
    double allTris = 0.0, hidTris = 0.0, hidEntries = 0.0;
    for (uint32_t i = 0; i < img.size(); ++i)
        if (img.kind[i] == sg::NodeKind::Geometry && img.draws[img.aux[i]].mesh)
            allTris += img.draws[img.aux[i]].mesh->triangleCount();
    for (uint32_t i = 0; i < img.size();) {
        if (!((h[i >> 6] >> (i & 63)) & 1u)) {
            ++i;
            continue;
        }
        hidEntries += img.end[i] - i;
        for (uint32_t j = i; j < img.end[i]; ++j)
            if (img.kind[j] == sg::NodeKind::Geometry && img.draws[img.aux[j]].mesh)
                hidTris += img.draws[img.aux[j]].mesh->triangleCount();
        i = img.end[i];
    }
    entries = hidEntries / double(img.size());
    tris = allTris > 0 ? hidTris / allTris : 0.0;
}
}  // namespace

int runPvs(const Args& a) {
    const std::string which = a.str("scene", "both");
    if (which != "city" && which != "office" && which != "both")
        throw std::invalid_argument("sgbench pvs: --scene must be city, office or both (got '" + which + "')");
    const std::string sweep = a.str("sweep", "both");
    if (sweep != "cells" && sweep != "occluders" && sweep != "both")
        throw std::invalid_argument("sgbench pvs: --sweep must be cells, occluders or both");
    const int res = int(a.num("resolution", 512));
    const double fixedCell = double(a.num("cell-size", 5));
    const uint32_t fixedOcc = uint32_t(a.num("max-occluders", 50));
    const std::string plane = a.str("plane", "both");
    if (plane != "both" && plane != "largest" && plane != "all")
        throw std::invalid_argument("sgbench pvs: --plane must be both, largest or all");
    for (const bool city : {true, false}) {
        if (which != "both" && city != (which == "city")) continue;
        const int n = int(a.num(city ? "n" : "r", city ? 100 : 8));
        if (n < 1 || n > 1000) throw std::invalid_argument("sgbench pvs: the scene size is not in 1..1000");
        sg::Scene scene(city ? scenes::buildCity({n, true}) : scenes::buildOffice(n));
        scene.update();
        std::vector<sg::Camera> cams;
        for (int f = 0; f < (city ? scenes::kStreetFrames : scenes::kWalkFrames); ++f)
            cams.push_back(city ? scenes::cityStreetCamera(n, f) : scenes::officeWalkCamera(n, f));
        struct Row {
            double cell;
            uint32_t occ;
        };
        std::vector<Row> rows;
        if (sweep != "occluders")
            for (double c : {2.0, 5.0, 10.0, 20.0}) rows.push_back({c, fixedOcc});
        if (sweep != "cells")
            for (uint32_t k : {5u, 20u, 50u, 100u, 200u}) rows.push_back({fixedCell, k});
        for (const Row& r : rows) {
            sg::PvsBuilder::Options o = pvsPathOptions(city, n, cams);
            o.cellSize = sg::dvec3(r.cell, r.cell, 2.0);
            o.maxOccluders = r.occ;
            o.resolution = res;
            o.plane = plane == "both"  ? sg::PvsBuilder::Plane::Both
                      : plane == "all" ? sg::PvsBuilder::Plane::BeyondAll
                                       : sg::PvsBuilder::Plane::BeyondLargest;
            sg::PvsBuilder::Stats st;
            const sg::PvsTable t = sg::PvsBuilder::build(scene, o, &st);
            double ent = 0, tri = 0;
            int inCells = 0;
            for (const sg::Camera& c : cams) {
                if (t.cellAt(c.eye()) < 0) continue;
                double e, tr;
                hiddenShare(scene.image(), t, c.eye(), e, tr);
                ent += e;
                tri += tr;
                ++inCells;
            }
            Json j;
            j.add("command", "pvs").add("scene", city ? "city" : "office").addInt(city ? "n" : "r", n);
            j.add("path", city ? "street" : "walk").add("cell_size", r.cell).addInt("max_occluders", long(r.occ));
            j.add("plane", plane)
                .addInt("resolution", res)
                .addInt("cells", long(t.cellCount()))
                .addInt("cells_built", long(st.cellsComputed));
            j.addInt("frames_in_cells", inCells);
            j.add("entries_hidden_percent", inCells ? 100.0 * ent / inCells : 0.0);
            j.add("triangles_hidden_percent", inCells ? 100.0 * tri / inCells : 0.0);
            j.add("build_ms", st.ms).add("ms_per_cell", st.cellsComputed ? st.ms / double(st.cellsComputed) : 0.0);
            j.add("occluders_drawn_per_cell", st.cellsComputed ? double(st.occluders) / double(st.cellsComputed) : 0.0);
            j.print(a);
        }
    }
    return 0;
}

}  // namespace bench
