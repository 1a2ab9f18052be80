// The cameras sgview starts from: the whole scene framed automatically, or the one given with --camera.
#pragma once
#include "common/FittedCamera.h"
#include "sg/core/Camera.h"
#include "sg/scene/Scene.h"
#include "sgview/Options.h"

namespace sgview {

using common::clipPlanes;
using common::kFovY;

// The world box of the scene's root (image entry 0); a 2 m box at the origin when the scene is empty or
// its bound is not finite, with `valid` false.
sg::Box sceneBound(const sg::Scene& scene, bool* valid = nullptr);

// Looks at the bound's centre from above its +X, "front" corner (-Y when up is +Z; +Z when up is +Y, glTF's
// front), about 30 degrees down, as close as keeps all 8 corners of the box in view.
sg::Camera autoCamera(const sg::Box& bound, const sg::dvec3& up, int width, int height);

// The camera of --camera, with its planes from the bound (common::fittedCamera).
sg::Camera specCamera(const CameraSpec& spec, const sg::Box& bound, int width, int height);

// What sgview renders first: specCamera when o.camera is set, else autoCamera.
sg::Camera startCamera(const Options& o, const sg::Box& bound, const sg::dvec3& up);

}  // namespace sgview
