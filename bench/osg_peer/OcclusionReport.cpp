// OcclusionReport: the occlusion mode's figures, as one JSON object (--json) or as a table.
#include <osg/Version>

#include <cstdio>
#include <vector>

#include "Json.h"
#include "Occlusion.h"

namespace osgbench {

namespace {

using namespace osgcity;

// The median over frames of a's time / b's time.
double perFrame(const Series& a, const Series& b) {
    std::vector<double> r;
    for (size_t i = 0; i < a.ms.size() && i < b.ms.size(); ++i) r.push_back(a.ms[i] / b.ms[i]);
    return median(r);
}

// k: the number of timed frames.
Json occlusionJson(const OcclusionOptions& o, const OcclusionRun& run, double k) {
    const Series& occ = run.osgOcc().s;
    const Series& off = run.osgOff().s;
    const Series& ign = run.osgIgn().s;
    Json j;
    j.addStr("peer", "openscenegraph").addStr("osg_version", osgGetVersion()).addInt("n", o.n);
    j.addStr("path", o.street ? "street" : "orbit").addBool("occlusion", true);
    j.addStr("osg_occluders", occluderKindName(o.occluders));
    j.addInt("occluder_polygons_per_building", long(run.meshes.occluders[0].size()));
    j.addInt("osg_max_active_occluders", o.maxOccluders).add("osg_min_occluder_volume", o.minVolume, 5);
    j.add("osg_occluder_range", o.occluderRange, 1);
    j.addInt("frames", run.frames).addInt("passes", o.passes);
    j.add("cull_ms_median", median(occ.ms)).add("cull_ms_p95", percentile95(occ.ms));
    j.add("geometries_mean", occ.geometries / k, 2).add("triangles_mean", occ.triangles / k, 1);
    j.add("active_occluders_mean", occ.occluders / k, 2);
    j.add("occluder_collect_ms_median", median(occ.collectMs));
    j.add("occluder_collect_ms_p95", percentile95(occ.collectMs));
    j.add("cull_ms_median_no_occlusion", median(off.ms)).add("cull_ms_p95_no_occlusion", percentile95(off.ms));
    j.add("geometries_mean_no_occlusion", off.geometries / k, 2);
    j.add("triangles_mean_no_occlusion", off.triangles / k, 1);
    j.add("cull_ms_median_occluders_ignored", median(ign.ms));
    j.add("cull_ms_p95_occluders_ignored", percentile95(ign.ms));
    j.add("triangles_mean_occluders_ignored", ign.triangles / k, 1);
    j.add("occlusion_over_frustum_triangles", occ.triangles / off.triangles);
    j.add("occlusion_over_frustum_cull_per_frame_median", perFrame(occ, off), 3);
    j.add("occluders_ignored_over_frustum_cull_per_frame_median", perFrame(ign, off), 3);
    j.addInt("occlusion_leaves_not_in_frustum_set", (long long)run.notSubset);
    j.add("build_s", run.buildSeconds).addInt("nodes", (long long)run.occScene.nodes);
    j.addInt("nodes_no_occlusion", (long long)run.plainScene.nodes);
#ifdef SGBENCH_WITH_SGKIT
    const Series& sgO = run.sgkit.o;
    const Series& sgF = run.sgkit.f;
    if (run.sgkit.scene) {
        j.add("sgkit_cull_ms_median", median(sgO.ms)).add("sgkit_cull_ms_p95", percentile95(sgO.ms));
        j.add("sgkit_geometries_mean", sgO.geometries / k, 2).add("sgkit_triangles_mean", sgO.triangles / k, 1);
        j.add("sgkit_occluders_used_mean", sgO.occluders / k, 2);
        j.add("sgkit_cull_ms_median_no_occlusion", median(sgF.ms));
        j.add("sgkit_cull_ms_p95_no_occlusion", percentile95(sgF.ms));
        j.add("sgkit_geometries_mean_no_occlusion", sgF.geometries / k, 2);
        j.add("sgkit_triangles_mean_no_occlusion", sgF.triangles / k, 1);
        j.add("sgkit_occlusion_over_frustum_triangles", sgO.triangles / sgF.triangles);
        j.add("sgkit_occlusion_over_frustum_cull_per_frame_median", perFrame(sgO, sgF), 3);
        j.add("osg_over_sgkit_per_frame_median", perFrame(occ, sgO), 3);
        j.add("osg_over_sgkit_per_frame_median_no_occlusion", perFrame(off, sgF), 3);
        j.add("osg_over_sgkit_triangles", occ.triangles / sgO.triangles);
    }
#endif
    return j;
}

void printRow(const char* name, const Series& s, bool occl, double k) {
    std::printf("%-38s %10.3f %10.3f %12.1f %12.1f", name, median(s.ms), percentile95(s.ms), s.geometries / k,
                s.triangles / k);
    if (occl) std::printf(" %10.2f", s.occluders / k);
    std::printf("\n");
}

void printTable(const OcclusionOptions& o, const OcclusionRun& run, double k) {
    const Series& occ = run.osgOcc().s;
    const Series& off = run.osgOff().s;
    const Series& ign = run.osgIgn().s;
    std::printf("sgbench_osg --occlusion: city N=%d, %s path, %d frames x %d pass(es), OpenSceneGraph %s\n", o.n,
                o.street ? "street" : "orbit", run.frames, o.passes, osgGetVersion());
    std::printf(
        "OSG occluders: %s (%zu ConvexPlanarOccluder polygons per building), at most %u active, "
        "minimum volume %g, ",
        occluderKindName(o.occluders), run.meshes.occluders[0].size(), o.maxOccluders, o.minVolume);
    if (o.occluderRange > 0.0)
        std::printf("within %g m (LOD)\n\n", o.occluderRange);
    else
        std::printf("no range limit\n\n");
    std::printf("%-38s %10s %10s %12s %12s %10s\n", "", "cull ms", "p95 ms", "geometries", "triangles", "occluders");
    printRow("OSG frustum only (no occluders)", off, false, k);
    printRow("OSG + shadow-volume occlusion", occ, true, k);
    printRow("OSG occluders, SHADOW_OCCLUSION off", ign, false, k);
#ifdef SGBENCH_WITH_SGKIT
    const Series& sgO = run.sgkit.o;
    const Series& sgF = run.sgkit.f;
    if (run.sgkit.scene) {
        printRow("sgkit frustum only", sgF, false, k);
        printRow("sgkit + occlusion tree", sgO, true, k);
    }
#endif
    std::printf("\nOSG occluder collection (part of the cull time above): median %.3f ms, p95 %.3f ms\n",
                median(occ.collectMs), percentile95(occ.collectMs));
    std::printf("\nper-frame medians of time ratios (same frame, same process):\n");
    std::printf("  OSG occlusion / OSG frustum only            %.3f   (triangles %.3f)\n", perFrame(occ, off),
                occ.triangles / off.triangles);
    std::printf("  OSG occluders ignored / OSG frustum only    %.3f\n", perFrame(ign, off));
#ifdef SGBENCH_WITH_SGKIT
    if (run.sgkit.scene) {
        std::printf("  sgkit occlusion / sgkit frustum only        %.3f   (triangles %.3f)\n", perFrame(sgO, sgF),
                    sgO.triangles / sgF.triangles);
        std::printf("  OSG / sgkit, frustum only                   %.3f\n", perFrame(off, sgF));
        std::printf("  OSG / sgkit, with occlusion                 %.3f   (triangles %.3f)\n", perFrame(occ, sgO),
                    occ.triangles / sgO.triangles);
    }
#endif
    std::printf("\nOSG occlusion draw leaves not drawn by OSG frustum only: %llu (expected 0)\n",
                (unsigned long long)run.notSubset);
}

}  // namespace

void reportOcclusion(const OcclusionOptions& o, const OcclusionRun& run) {
    const double k = double(run.osgOcc().s.ms.size());
    if (o.json)
        std::printf("%s\n", occlusionJson(o, run, k).str().c_str());
    else
        printTable(o, run, k);
}

}  // namespace osgbench
