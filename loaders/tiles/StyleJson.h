// A 3D Tiles style read from its JSON (the spec's Styling: show, color, pointSize and defines).
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError
#include "sg/style/Style.h"

#include <string>
#include <vector>

namespace sg {

// show (a boolean, an expression or {"conditions": [[condition, expression], ...]}), color (an expression or
// conditions), pointSize (a number, an expression or conditions) and defines (name: expression). An expression
// that does not parse is a LoadError naming its JSON path ("color.conditions[1][0]") and the StyleError's text;
// meta and members the reader does not know are left out with a warning naming them.
Style parseStyleJson(const std::string& file, const std::string& text, std::vector<std::string>* warnings = nullptr);

}  // namespace sg
