// libFuzzer target for the metadata JSON reader (loaders/metadata/internal/MetadataJson.h) and the property store it
// fills (sg/core/Properties.h). The input is JSON text, a NUL byte, then the binary buffer the table reads:
//   {"schema": {...}, "propertyTable": {...}, "bufferViews": [{"byteOffset": 0, "byteLength": 8}, ...]} \0 bytes
// The schema and table are parsed, the table added, then every property of every row read and printed, and every
// property decoded from the buffer's bytes. Only sg::LoadError (bad JSON content) and std::invalid_argument (a table
// the store refuses) may escape a step; anything else (a crash, a sanitizer report, another exception, a hang past
// -timeout) is a finding. The seed corpus is in fuzz/metadata-corpus/.
#include "loaders/metadata/internal/MetadataJson.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

// Rows read per table: enough to reach every kind of element, bounded so one input stays fast.
constexpr uint64_t kMaxRows = 512;

sg::ByteSpan viewOf(const json& views, uint64_t bufferSize, int64_t index, const std::string& path) {
    if (!views.is_array() || index < 0 || uint64_t(index) >= views.size())
        throw sg::LoadError("fuzz.json", path, "no bufferView " + std::to_string(index));
    const json& v = views[size_t(index)];
    const json* offset = v.is_object() && v.contains("byteOffset") ? &v["byteOffset"] : nullptr;
    const json* length = v.is_object() && v.contains("byteLength") ? &v["byteLength"] : nullptr;
    if (!offset || !length || !offset->is_number_unsigned() || !length->is_number_unsigned())
        throw sg::LoadError("fuzz.json", path, "bufferView without byteOffset and byteLength");
    const uint64_t o = offset->get<uint64_t>(), n = length->get<uint64_t>();
    if (o > bufferSize || n > bufferSize - o) throw sg::LoadError("fuzz.json", path, "bufferView past the buffer");
    return sg::ByteSpan{0, o, n};
}

void readAll(const sg::PropertyStore& store, int t) {
    const sg::PropertyTable& table = store.tables()[size_t(t)];
    const uint64_t rows = std::min(table.count, kMaxRows);
    for (uint64_t r = 0; r <= rows; ++r) {  // one past the last read row too (Null past the table)
        const uint64_t row = r == rows ? table.count : r;
        for (const auto& [id, value] : store.row(t, row)) {
            (void)value.toString();
            (void)value.toJson();
            (void)sg::metadata::jsonOf(value).dump(-1, ' ', false,
                                                   json::error_handler_t::replace);  // strings: any bytes
        }
    }
}

void decodeAll(const sg::PropertyStore& store, const std::vector<uint8_t>& bytes) {
    for (size_t c = 0; c < store.schema.classes.size(); ++c)
        for (size_t p = 0; p < store.schema.classes[c].properties.size(); ++p)
            for (size_t size : {size_t(0), size_t(1), size_t(4), bytes.size()})
                if (size <= bytes.size()) (void)store.decode(int(c), int(p), bytes.data(), size, {}).toString();
}

void run(const uint8_t* data, size_t size) {
    const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
    const size_t textSize = nul ? size_t(nul - data) : size;
    const json j = json::parse(data, data + textSize, nullptr, false);
    if (!j.is_object()) return;
    std::vector<uint8_t> buffer(nul ? nul + 1 : data + size, data + size);

    std::vector<std::string> warnings;
    const sg::metadata::Context context{"fuzz.json", &warnings};
    auto store = sg::make<sg::PropertyStore>();
    try {
        store->schema = sg::metadata::parseSchema(j.value("schema", json::object()), context, "schema");
        (void)sg::metadata::schemaJson(store->schema).dump(-1, ' ', false, json::error_handler_t::replace);
    } catch (const sg::LoadError&) {
        return;
    }
    const uint64_t bufferSize = buffer.size();
    store->addBuffer(buffer);
    decodeAll(*store, buffer);
    const json views = j.value("bufferViews", json::array());
    sg::metadata::ViewLookup lookup = [&](int64_t index, const std::string& path) {
        return viewOf(views, bufferSize, index, path);
    };
    if (!j.contains("propertyTable")) return;
    int t = -1;
    try {
        t = store->addTable(
            sg::metadata::parsePropertyTable(j["propertyTable"], store->schema, lookup, context, "propertyTable"));
    } catch (const sg::LoadError&) {
        return;
    } catch (const std::invalid_argument&) {
        return;
    }
    readAll(*store, t);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    run(data, size);
    return 0;
}
