// sgview's two ways of showing a loaded scene; each returns the process exit code.
#pragma once
#include "sg/scene/Scene.h"
#include "sgview/LoadScene.h"
#include "sgview/Options.h"

namespace sgview {

// Renders o.frames frames offscreen and writes the last one to o.out (with the overlay when o.overlay).
int runHeadless(const Options& o, sg::Scene& scene, const LoadedScene& loaded);
// The window: navigation, the overlay, culling keys, screenshots, picking; until closed (or o.frames frames).
int runWindow(const Options& o, sg::Scene& scene, const LoadedScene& loaded);

}  // namespace sgview
