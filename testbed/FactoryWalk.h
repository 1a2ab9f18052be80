// The factory walkthrough's scripted path: an eye moved by the viewpoint collider from an outside approach into a
// workshop, along its machines, out again, round the site and up to an overview, with the Switch state
// (which workshop the eye is in) decided at every step.
#pragma once
#include "sg/core/Camera.h"
#include "sg/scene/Scene.h"
#include "testbed/Factory.h"

#include <string>
#include <vector>

namespace scenes {

struct PathFrame {
    sg::dvec3 eye{0.0}, target{0.0};
    int workshop = -1;     // factoryWorkshopAt(eye): the Switch state this frame is drawn with
    bool walking = false;  // eye at terrainHeight + 1.7 (else flying)
    std::string segment;   // approach, enter, machines, leave, circle, overview
};

struct WalkPath {
    std::vector<PathFrame> frames;
    int penetrations = 0;    // steps that ended with collidable geometry nearer than the eye radius
    int insideFrames = 0;    // frames with the eye inside a workshop (its Switch on, the outside off)
    int workshop = 0;        // the workshop walked through
    double eyeRadius = 0.3;  // the collider's sphere
};

// Clears kCollidable from every workshop's exterior and its interior shell (inner wall faces, floor and
// ceiling), so that the eye walks through workshop walls as in the paper; every other node keeps it.
void makeWorkshopWallsPassable(Factory& f);

// Moves the eye along the script with a ViewpointCollider over `scene` (the factory's root), switching the
// workshops as it goes; leaves the factory with the defaults (setFactoryEye(f, -1)) and the scene updated.
// Throws std::invalid_argument for fewer than 10 frames.
WalkPath buildWalkPath(Factory& f, sg::Scene& scene, int frames);

// The camera of a path frame: fov 60, near 0.1 (walking) or 1 (flying), far 3000.
sg::Camera pathCamera(const PathFrame& p, int width, int height);

}  // namespace scenes
