// PointShading: how the renderer draws points and lines (sizes in pixels of the target), and eye-dome lighting.
#pragma once

namespace sg {

struct PointShading {
    // Points: squares of `pointSize` pixels, or with `attenuate` each point as large as its mesh's point spacing
    // (Mesh::pointSpacing(), scaled by `spacingScale`) appears on screen at its depth, clamped to [pointSize,
    // maxPointSize] (CesiumJS's point cloud attenuation); a mesh without a spacing keeps pointSize.
    float pointSize = 2.0f;
    bool attenuate = false;
    float maxPointSize = 8.0f;
    float spacingScale = 1.0f;
    // Discs instead of squares (fragments outside the inscribed circle are not drawn).
    bool round = false;
    // Lines and outlines (Mesh::outline()), in pixels.
    float lineWidth = 1.0f;
    // Eye-dome lighting (Boucheny's, as Potree and CesiumJS have it): after the items are drawn, each pixel is
    // darkened by how far its neighbours `eyeDomeRadius` pixels away lie in front of it in log depth, times
    // `eyeDomeStrength`; it gives points without normals their shape. Shades the whole frame (triangles too).
    bool eyeDome = false;
    float eyeDomeStrength = 1.0f;
    float eyeDomeRadius = 1.0f;
};

}  // namespace sg
