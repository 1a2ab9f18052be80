// The `pcvr-city` scene: the city walkthrough of Qi, Pan, Xu and Zhang's conservative-visibility paper (PCVR,
// 2000), built to its description: 25 objects (15 buildings, 4 streets, 6 cars), 23,400 triangles exactly, seen
// at 1024x768 from a car driving round the streets at eye height.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Camera.h"

#include <cstdint>

namespace scenes {

constexpr int kPcvrObjects = 25;
constexpr uint32_t kPcvrTriangles = 23400;
constexpr int kPcvrFrames = 240;

// Four streets 12 m wide and 400 m long in a # (centre lines at 100 and 300 m along x and y), 15 buildings in the
// nine blocks between them (facades gridded, heights 10 to 60 m), 6 cars on the streets. The seed picks the
// heights, the facade grids and the cars' places; the streets' grids take up the rest of the 23,400 triangles.
// Every object is one Geometry under a Transform, its triangles in spatially coherent order (facade rows).
sg::ref_ptr<sg::Group> buildPcvrCity(uint64_t seed = 1);
// Frame f of kPcvrFrames (wraps): round the inner square of the streets (100..300 m), eye 1.5 m high, looking
// along the street with a slow sway; fov 60 vertical, near 0.5, far 250 m.
sg::Camera pcvrCityCamera(int frame, int width = 1024, int height = 768);

}  // namespace scenes
