#include "map/OsmesaDisplay.h"

namespace sgmap {

OsmesaDisplay::OsmesaDisplay(int width, int height) : context_(width, height) {}

void OsmesaDisplay::draw(const sg::DrawList& list, const sg::Camera& camera, const std::string& overlay) {
    renderer_.draw(list, camera, kSeaColor);
    if (!overlay.empty()) overlay_.draw(overlay, camera.width(), camera.height(), 2.0f);
    renderer_.finish();  // whole-frame times
}

}  // namespace sgmap
