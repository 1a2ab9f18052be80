// OsmesaDisplay: the map drawn offscreen through OSMesa (the headless program and the tests).
#pragma once
#include "map/Display.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

namespace sgmap {

class OsmesaDisplay : public Display {
public:
    OsmesaDisplay(int width, int height) : context_(width, height) {}
    sg::Renderer& renderer() override { return renderer_; }
    void bindContext(bool current) override { current ? context_.makeCurrent() : context_.release(); }

private:
    sg::OsmesaContext context_;  // first: the renderer needs it current
    sg::Renderer renderer_;
};

}  // namespace sgmap
