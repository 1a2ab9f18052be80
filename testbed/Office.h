// The `office` benchmark scene (rooms, walls with doors as box occluders, shared furniture) and its walk
// path, as docs/scenes.md describes them.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Camera.h"

namespace scenes {

struct OfficeCounts {
    int rooms = 0, wallBoxes = 0, furnitureBoxes = 0;
};

// R x R rooms; every wall box is a Geometry and, beside it, a box Occluder.
sg::ref_ptr<sg::Group> buildOffice(int r, OfficeCounts* counts = nullptr);

constexpr int kWalkFrames = 240;
// Viewport 1280x720, fov 60, near 0.1, far 200; frame f of 240.
sg::Camera officeWalkCamera(int r, int frame, int width = 1280, int height = 720);

}  // namespace scenes
