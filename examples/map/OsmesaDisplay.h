// OsmesaDisplay: the map drawn offscreen through OSMesa (the headless program and the tests).
#pragma once
#include "map/Display.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/gl/TextOverlay.h"

namespace sgmap {

class OsmesaDisplay : public Display {
public:
    OsmesaDisplay(int width, int height);
    void draw(const sg::DrawList& list, const sg::Camera& camera, const std::string& overlay) override;
    sg::Image read() override { return renderer_.readColor(); }
    void releaseUnused() override { renderer_.releaseUnused(); }
    const sg::Renderer& renderer() const { return renderer_; }

private:
    sg::OsmesaContext context_;  // first: the renderer needs it current
    sg::Renderer renderer_;
    sg::TextOverlay overlay_;
};

}  // namespace sgmap
