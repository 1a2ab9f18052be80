// A style evaluated for every feature of a property table: the per-feature colours a renderer uploads.
#pragma once
#include "sg/core/Properties.h"
#include "sg/style/Style.h"

#include <cstdint>
#include <vector>

namespace sg {

struct StyledTable {
    // RGBA8 per feature (row), 4 bytes each; (0, 0, 0, 0) for a hidden feature.
    std::vector<uint8_t> rgba;
    // Per feature, the point size (1 for a hidden feature); empty when every feature's is 1.
    std::vector<float> pointSizes;
};

// The binder of a style over the class of table `table` of `store`: a name is the class property of that id
// (its slot is the property's index), of the kind its values read as (Number, String for strings and enums,
// Boolean, vec2..vec4; unknown for arrays and matrices); any other name has no slot (undefined).
StyleBinder propertyTableBinder(const PropertyStore& store, int table);

// `style` bound to the table and evaluated for each of its rows. std::out_of_range for a bad table index,
// std::length_error for a row count no vector holds;
// StyleError from binding (a property of a kind its operator cannot take) or from a feature's evaluation.
StyledTable styleTable(const Style& style, const PropertyStore& store, int table);

}  // namespace sg
