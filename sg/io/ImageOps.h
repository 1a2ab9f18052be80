// Pixel work on RGBA8 images before they become textures: what the renderer does on the CPU.
#pragma once
#include "sg/io/ImageIO.h"

namespace sg {

// Gives the texels with alpha 0 the colour of their nearest visible texels, ring by ring (each the rounded
// average of its 4-neighbours filled before it); alpha and the visible texels stay as they are. Filtering and
// mipmaps at a cut-out edge then mix only colours of the picture, never the hidden ones, which are often black
// or white. An image without a visible texel is left as it is. Throws std::invalid_argument when the pixel
// count does not match width x height.
void bleedIntoTransparent(Image& img);

}  // namespace sg
