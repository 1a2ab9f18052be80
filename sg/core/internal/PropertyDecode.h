// How the property store turns stored bytes into values (sg/core/Properties.h): components read little-endian, enum
// values named, noData made the default, then normalized, offset and scaled. Shared by tables, textures and
// attributes. Internal header: not installed (an internal/ folder, cmake/LayerCheck.cmake).
#pragma once
#include "sg/core/Properties.h"

#include <cstddef>
#include <cstdint>

namespace sg::props {

// The component type an element of `p` is stored as: the enum's value type for Enum (None for a bad enum index),
// else the property's own.
ComponentType storedType(const Schema& schema, const ClassProperty& p);
bool isInteger(ComponentType c);
// Bytes per element of a fixed-size type (Scalar, VECn, MATn, Enum); 0 for String, Boolean and no component type.
size_t elementBytes(const Schema& schema, const ClassProperty& p);

// One component at `at`, raw: Integer for signed integer types, Unsigned for unsigned ones, Number for floats.
PropertyValue readComponent(ComponentType c, const uint8_t* at);
// An offset of a string or array offset buffer (UInt8..UInt64); 0 for another type.
uint64_t readOffset(ComponentType c, const uint8_t* at);
// One raw element of a fixed-size type at `at` (elementBytes() bytes): a component, or an Array of them for VECn and
// MATn (column-major, as stored).
PropertyValue readElement(const Schema& schema, const ClassProperty& p, const uint8_t* at);
// An enum's raw value (Integer or Unsigned) as the int64 its EnumDef lists.
int64_t enumRaw(const PropertyValue& raw);

// What a program reads from a raw value (one element, or an Array of elements for an array property): enum values
// by name (Null for an unnamed one), a value equal to noData made the default (Null without one), then numbers
// normalized, then offset + scale * value, element-wise (`o` wins over the class's offset and scale).
PropertyValue finish(const Schema& schema, const ClassProperty& p, PropertyValue raw, const PropertyOverrides& o);

}  // namespace sg::props
