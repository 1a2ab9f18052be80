// The factory site's textures, generated at build time from a seed: RGBA8, tileable, mipmapped by the renderer.
#pragma once
#include "sg/core/Material.h"

#include <cstdint>

namespace scenes {

// The wall textures keep their top-left 2x2 texels pure white, so that the parts of a building that are
// not wall (trim, vents: uv kFactoryWhiteUv) take their colour from their vertices alone. All but the
// tree wrap without a seam: the last column continues into the first, and on the ground and roof
// textures the last row into the first.

// Texture coordinate of that white corner: its texel (0, 0) at 64 texels, the corner of four at 128.
constexpr float kFactoryWhiteUv = 0.5f / 64.0f;

// 64x64, one bay of one storey of a rendered wall: white (tinted by the vertex colour) with faint joints, a
// window at u 0.25..0.75, v 0.3..0.8.
sg::ref_ptr<sg::Texture> factoryWindowTexture();
// 128x128, one bay of one storey of a brick wall in stretcher bond (its own colour: draw with white
// vertices), a concrete band at the top and the same window as factoryWindowTexture().
sg::ref_ptr<sg::Texture> factoryBrickTexture(uint32_t seed);
// 128x128, corrugated metal roofing, grey with weathering; u across the ribs. Metres per repeat: 4.
sg::ref_ptr<sg::Texture> factoryRoofTexture(uint32_t seed);
constexpr float kFactoryRoofMetres = 4.0f;
// 128x128, grass seen from above: blades and clumps around a mean near white, tinted by the terrain's
// vertex colours. Metres per repeat: 6.
sg::ref_ptr<sg::Texture> factoryGrassTexture(uint32_t seed);
constexpr float kFactoryGrassMetres = 6.0f;
// 128x128, asphalt: grain, stones and patches around a light grey, tinted by the road's vertex colours
// (paint included). Metres per repeat: 4.
sg::ref_ptr<sg::Texture> factoryAsphaltTexture(uint32_t seed);
constexpr float kFactoryAsphaltMetres = 4.0f;
// 64x64 tree for an axial billboard: a trunk and a round crown of foliage, alpha 0 around them.
sg::ref_ptr<sg::Texture> factoryTreeTexture(uint32_t seed);

}  // namespace scenes
