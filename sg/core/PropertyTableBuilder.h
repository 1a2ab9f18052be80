// Makes a property table from typed rows, so that a program gives its own scenes' features properties without
// writing bytes: columns declared by type, rows appended as values, the table written into a PropertyStore in the
// binary layout EXT_structural_metadata and 3D Tiles 1.1 define (one buffer, each column 8-byte aligned).
#pragma once
#include "sg/core/Features.h"
#include "sg/core/Properties.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg {

class PropertyTableBuilder {
public:
    // A table of a new class `classId` (added to the store's schema by finish()); `tableName` names the table.
    explicit PropertyTableBuilder(std::string classId, std::string tableName = {});

    // Columns, in the class's order; each returns the column's index. Scalar takes any numeric component type.
    int addScalar(std::string id, ComponentType type);
    int addString(std::string id);
    int addBoolean(std::string id);
    // An enum column: a new enum `enumId` of the schema whose names take the values 0, 1, 2... (UINT16).
    int addEnum(std::string id, std::string enumId, const std::vector<std::string>& names);

    // One row, a value per column in column order: a number (Integer, Unsigned or Number) for a scalar (integers
    // must fit the component type), a String for a string, a Boolean for a boolean, an enum's name as a String.
    // std::invalid_argument naming the column when a value does not fit; nothing appended then.
    void addRow(const std::vector<PropertyValue>& values);
    uint64_t rows() const { return rows_; }

    // The columns' bytes as finish() writes them: one buffer, each column starting at a multiple of 8.
    std::vector<uint8_t> bytes() const;
    // Adds the class (and its enums) to the store's schema, the bytes as a buffer and the table; returns the
    // table's index. std::invalid_argument when the store already has the class or an enum, or refuses the table.
    int finish(PropertyStore& store) const;

private:
    struct Column {
        ClassProperty property;
        std::vector<std::string> enumNames;  // an enum column's names, by value
        std::string enumId;
        std::vector<uint8_t> values;          // little-endian values; a boolean column's bits, LSB first
        std::vector<uint32_t> stringOffsets;  // a string column's byte offsets, rows + 1 of them
    };
    int add(Column c);
    void append(Column& c, const PropertyValue& v) const;
    std::string check(const Column& c, const PropertyValue& v) const;  // why `v` does not fit; empty when it does

    std::string classId_, tableName_;
    std::vector<Column> columns_;
    uint64_t rows_ = 0;
};

// The feature ID set a program's nodes name by index (Node::setFeatures(set, i) for row i of `table`): one set of
// Source::Instance whose ids are 0..rows-1, with the table and the store it reads.
ref_ptr<MeshFeatures> rowFeatures(ref_ptr<const PropertyStore> store, int table, std::string label = {});

}  // namespace sg
