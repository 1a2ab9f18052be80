// CSS colour text as the styling language's color() takes it: a keyword (case-insensitive), "#rgb" or "#rrggbb".
#pragma once
#include <array>
#include <optional>
#include <string>

namespace sg::style {

// RGBA in 0..1 (alpha 1; "transparent" has 0), or nullopt for text that is none of those.
std::optional<std::array<double, 4>> parseCssColor(const std::string& text);

}  // namespace sg::style
