// The factory site as both the walkthrough and the window show it: built, and lit by the baked sun and ambient
// occlusion unless the options say not to.
#pragma once
#include "factory/Options.h"
#include "testbed/Factory.h"

namespace factory {

// scenes::buildFactory(), then with o.lighting scenes::bakeFactoryLighting() through the cache in o.cacheDir
// (or the baker's default); says what it does on stderr. Throws as those do.
scenes::Factory buildSite(const Options& o);

}  // namespace factory
