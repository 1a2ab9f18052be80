// The PLY reader behind openScan: the header parsed once, then the `vertex` element's records streamed a chunk at a
// time (ascii, binary little or big endian). Elements before `vertex` are skipped on open, those after it never read.
#include "loaders/points/internal/ScanFormats.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sg {

namespace {

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Encoding : uint8_t { Ascii, Little, Big };
// What a vertex property is for; None: read and dropped.
enum Role : uint8_t { kNone, kX, kY, kZ, kRed, kGreen, kBlue, kAlpha, kNx, kNy, kNz, kIntensity, kRoles };

constexpr size_t kMaxHeaderBytes = size_t(1) << 20;  // a header larger than this is not a scan's
constexpr size_t kChunkBytes = size_t(1) << 20;      // binary records read at once

size_t sizeOf(Type t) {
    static const size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[size_t(t)];
}

bool parseType(const std::string& s, Type& t) {
    static const char* const names[][2] = {{"char", "int8"},     {"uchar", "uint8"},   {"short", "int16"},
                                           {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                                           {"float", "float32"}, {"double", "float64"}};
    for (size_t i = 0; i < 8; ++i)
        if (s == names[i][0] || s == names[i][1]) return t = Type(i), true;
    return false;
}

Role roleOf(const std::string& name) {
    static const char* const names[] = {"",     "x",     "y",  "z",  "red", "green",
                                        "blue", "alpha", "nx", "ny", "nz",  "intensity"};
    for (size_t r = 1; r < kRoles; ++r)
        if (name == names[r]) return Role(r);
    return name == "scalar_intensity" ? kIntensity : kNone;
}

struct Property {
    std::string name;
    Type type = Type::U8;
    bool list = false;
    Type countType = Type::U8;  // a list's
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
    bool fixed() const {
        return std::none_of(props.begin(), props.end(), [](const Property& p) { return p.list; });
    }
    size_t stride() const {
        size_t n = 0;
        for (const Property& p : props) n += sizeOf(p.type);
        return n;
    }
};

// One scalar of binary data, in the file's byte order, as a double.
double decode(const uint8_t* p, Type t, bool swap) {
    uint8_t b[8];
    const size_t n = sizeOf(t);
    for (size_t i = 0; i < n; ++i) b[i] = swap ? p[n - 1 - i] : p[i];
    auto as = [&b](auto v) {
        std::memcpy(&v, b, sizeof v);
        return double(v);
    };
    switch (t) {
        case Type::I8: return as(int8_t());
        case Type::U8: return as(uint8_t());
        case Type::I16: return as(int16_t());
        case Type::U16: return as(uint16_t());
        case Type::I32: return as(int32_t());
        case Type::U32: return as(uint32_t());
        case Type::F32: return as(float());
        case Type::F64: return as(double());
    }
    return 0.0;
}

// A colour channel to 8 bits: 8-bit values as they are, 16-bit ones by their high byte, floats from 0..1.
uint8_t colour8(double v, Type t) {
    if (!(v > 0.0)) return 0;  // NaN too
    if (t == Type::F32 || t == Type::F64) return uint8_t(std::lround(std::min(v, 1.0) * 255.0));
    if (t == Type::U16 || t == Type::I16) return uint8_t(std::min(v, 65535.0) / 256.0);
    return uint8_t(std::min(v, 255.0));
}

class PlyReader final : public ScanReader {
public:
    explicit PlyReader(const std::string& path);
    size_t read(std::vector<ScanPoint>& out, size_t max) override;
    void rewind() override;

private:
    [[noreturn]] void fail(const std::string& reason) const;
    void parseHeader();
    void headerLine(const std::string& line, std::vector<Element>& elements);
    void skipElement(const Element& e);
    bool readBinaryRecord(const Element& e, std::vector<double>& values);
    bool readAsciiRecord(const Element& e, std::vector<double>& values);
    ScanPoint point(const std::vector<double>& values) const;

    std::string path_;
    std::ifstream in_;
    uint64_t fileSize_ = 0;
    Encoding encoding_ = Encoding::Ascii;
    bool swap_ = false;   // binary in the other byte order than the host's
    bool header_ = true;  // errors name the header's line
    Element vertex_;
    int role_[kRoles];                            // the vertex property of each role, -1: none
    uint64_t vertexOffset_ = 0, vertexLine_ = 0;  // where the vertex records start
    uint64_t offset_ = 0, line_ = 0, next_ = 0;   // the reader's byte offset, ascii line, next vertex
    std::vector<uint8_t> chunk_;
    std::vector<double> values_;
};

PlyReader::PlyReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw LoadError(path_, "", "cannot open the file");
    in_.seekg(0, std::ios::end);
    fileSize_ = uint64_t(in_.tellg());
    in_.seekg(0);
    std::fill(std::begin(role_), std::end(role_), -1);
    parseHeader();
}

void PlyReader::fail(const std::string& reason) const {
    const bool byLine = header_ || encoding_ == Encoding::Ascii;
    throw LoadError(path_, byLine ? "line " + std::to_string(line_) : "offset " + std::to_string(offset_), reason);
}

// The header line by line up to end_header, then the elements before `vertex` skipped.
void PlyReader::parseHeader() {
    // At most kMaxHeaderBytes are looked at: a file without line breaks is not read whole into memory.
    std::string head(size_t(std::min<uint64_t>(fileSize_, kMaxHeaderBytes)), '\0');
    in_.read(head.data(), std::streamsize(head.size()));
    std::vector<Element> elements;
    size_t pos = 0;
    for (bool ended = false; !ended;) {
        const size_t eol = head.find('\n', pos);
        if (eol == std::string::npos)
            fail(head.size() < kMaxHeaderBytes
                     ? "the header has no end_header"
                     : "no end_header in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
        std::string line = head.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line_ == 1 && line != "ply") fail("not a PLY file (the first line is not \"ply\")");
        ended = line == "end_header";
        if (line_ > 1 && !ended) headerLine(line, elements);
    }
    if (info_.format.empty()) fail("the header has no format line");
    offset_ = pos;
    in_.clear();
    in_.seekg(std::streamoff(pos));
    auto v = std::find_if(elements.begin(), elements.end(), [](const Element& e) { return e.name == "vertex"; });
    if (v == elements.end()) fail("the header has no vertex element");
    vertex_ = *v;
    for (size_t i = 0; i < vertex_.props.size(); ++i) {
        const Role r = vertex_.props[i].list ? kNone : roleOf(vertex_.props[i].name);
        if (r != kNone && role_[r] < 0) role_[r] = int(i);
    }
    if (role_[kX] < 0 || role_[kY] < 0 || role_[kZ] < 0) fail("the vertex element has no x, y and z");
    info_.count = vertex_.count;
    info_.hasColor = role_[kRed] >= 0 && role_[kGreen] >= 0 && role_[kBlue] >= 0;
    info_.hasIntensity = role_[kIntensity] >= 0;
    info_.hasNormal = role_[kNx] >= 0 && role_[kNy] >= 0 && role_[kNz] >= 0;
    header_ = false;
    for (auto e = elements.begin(); e != v; ++e) skipElement(*e);
    // Ascii records are read by line, without counting bytes: the stream says where the vertices start.
    offset_ = vertexOffset_ = uint64_t(in_.tellg());
    vertexLine_ = line_;
    if (encoding_ != Encoding::Ascii && vertex_.fixed()) {  // a count past the data is refused before any read
        const uint64_t stride = vertex_.stride(), left = fileSize_ - std::min(fileSize_, offset_);
        if (stride > 0 && vertex_.count > left / stride)
            fail("the vertex element's " + std::to_string(vertex_.count) + " records of " + std::to_string(stride) +
                 " bytes do not fit in the " + std::to_string(left) + " bytes left in the file");
    }
}

void PlyReader::headerLine(const std::string& line, std::vector<Element>& elements) {
    std::istringstream words(line);
    std::string key, a, b, c, d;
    words >> key;
    if (key.empty() || key == "comment" || key == "obj_info") return;
    if (key == "format") {
        words >> a >> b;
        if (a == "ascii")
            encoding_ = Encoding::Ascii;
        else if (a == "binary_little_endian")
            encoding_ = Encoding::Little;
        else if (a == "binary_big_endian")
            encoding_ = Encoding::Big;
        else
            fail("unknown format \"" + a + "\"");
        if (b != "1.0") fail("format version \"" + b + "\" (1.0 is read)");
        const uint16_t one = 1;
        uint8_t low = 0;
        std::memcpy(&low, &one, 1);
        swap_ = encoding_ == (low == 1 ? Encoding::Big : Encoding::Little);
        info_.format = "PLY " + a;
    } else if (key == "element") {
        words >> a >> b;
        char* end = nullptr;
        errno = 0;
        const unsigned long long n = std::strtoull(b.c_str(), &end, 10);
        if (a.empty() || b.empty() || b[0] == '-' || *end != '\0' || errno != 0)
            fail("element \"" + a + "\" has no count that is a whole number (\"" + b + "\")");
        elements.push_back(Element{a, n, {}});
    } else if (key == "property") {
        if (elements.empty()) fail("a property before any element");
        Property p;
        words >> a >> b >> c >> d;
        const bool ok = a == "list" ? parseType(b, p.countType) && parseType(c, p.type) && !(p.name = d).empty()
                                    : parseType(a, p.type) && !(p.name = b).empty();
        if (!ok) fail("property \"" + line + "\" has an unknown type or no name");
        p.list = a == "list";
        if (p.list && (p.countType == Type::F32 || p.countType == Type::F64)) fail("a list counted by a float");
        elements.back().props.push_back(p);
    } else {
        fail("unknown header line \"" + line + "\"");
    }
}

// Skips an element before `vertex`: binary fixed-size records at once (checked against the file's size), others
// record by record.
void PlyReader::skipElement(const Element& e) {
    if (encoding_ != Encoding::Ascii && e.fixed()) {
        const uint64_t stride = e.stride(), left = fileSize_ - std::min(fileSize_, offset_);
        if (stride > 0 && e.count > left / stride)
            fail("element \"" + e.name + "\"'s " + std::to_string(e.count) + " records of " + std::to_string(stride) +
                 " bytes do not fit in the " + std::to_string(left) + " bytes left in the file");
        offset_ += e.count * stride;
        in_.seekg(std::streamoff(offset_));
        return;
    }
    std::vector<double> values;
    for (uint64_t i = 0; i < e.count; ++i) {
        const bool ok = encoding_ == Encoding::Ascii ? readAsciiRecord(e, values) : readBinaryRecord(e, values);
        if (!ok)
            fail("the file ends in element \"" + e.name + "\" after " + std::to_string(i) + " of its " +
                 std::to_string(e.count) + " records");
    }
}

// One record property by property (lists' items skipped); false at the end of the file.
bool PlyReader::readBinaryRecord(const Element& e, std::vector<double>& values) {
    values.assign(e.props.size(), 0.0);
    uint8_t b[8];
    for (size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        const Type t = p.list ? p.countType : p.type;
        if (!in_.read(reinterpret_cast<char*>(b), std::streamsize(sizeOf(t)))) return false;
        offset_ += sizeOf(t);
        values[i] = decode(b, t, swap_);
        if (!p.list) continue;
        const uint64_t left = fileSize_ - std::min(fileSize_, offset_);
        if (!(values[i] >= 0.0) || values[i] * double(sizeOf(p.type)) > double(left))
            fail("list \"" + p.name + "\" of " + std::to_string(values[i]) + " items reaches past the file's end");
        offset_ += uint64_t(values[i]) * sizeOf(p.type);
        in_.seekg(std::streamoff(offset_));
    }
    return true;
}

// One line of whitespace-separated values (a list: its count, then its items, skipped); false at the end of the file.
bool PlyReader::readAsciiRecord(const Element& e, std::vector<double>& values) {
    std::string text;
    do {
        if (!std::getline(in_, text)) return false;
        ++line_;
    } while (text.find_first_not_of(" \t\r") == std::string::npos);  // blank lines between records
    std::istringstream words(text);
    std::string word;
    values.assign(e.props.size(), 0.0);
    for (size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (!(words >> word)) fail(e.name + " record has no value for \"" + p.name + "\"");
        char* end = nullptr;
        values[i] = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0') fail("\"" + word + "\" is not a number (\"" + p.name + "\")");
        if (!p.list) continue;
        if (!(values[i] >= 0.0 && values[i] <= double(text.size())) || values[i] != std::floor(values[i]))
            fail("list \"" + p.name + "\" has a count of " + word);
        for (uint64_t k = 0; k < uint64_t(values[i]); ++k)
            if (!(words >> word))
                fail("list \"" + p.name + "\" has " + std::to_string(k) + " items, fewer than its count " +
                     std::to_string(uint64_t(values[i])));
    }
    if (words >> word)
        fail(e.name + " record has more values than its " + std::to_string(e.props.size()) + " properties (\"" + word +
             "\")");
    return true;
}

ScanPoint PlyReader::point(const std::vector<double>& v) const {
    ScanPoint p;
    p.position = dvec3(v[size_t(role_[kX])], v[size_t(role_[kY])], v[size_t(role_[kZ])]);
    if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z))
        fail("point " + std::to_string(next_) + " has a position that is not finite");
    const Role channels[] = {kRed, kGreen, kBlue, kAlpha};
    for (int c = 0; c < 4; ++c)
        if (role_[channels[c]] >= 0) {
            const size_t i = size_t(role_[channels[c]]);
            p.color[c] = colour8(v[i], vertex_.props[i].type);
        }
    if (info_.hasNormal)
        p.normal = vec3(float(v[size_t(role_[kNx])]), float(v[size_t(role_[kNy])]), float(v[size_t(role_[kNz])]));
    if (info_.hasIntensity) {  // integers as they are, clamped to 16 bits; NaN: 0
        const double i = v[size_t(role_[kIntensity])];
        p.intensity = i > 0.0 ? uint16_t(std::lround(std::min(i, 65535.0))) : 0;
    }
    return p;
}

size_t PlyReader::read(std::vector<ScanPoint>& out, size_t max) {
    out.clear();
    const uint64_t n = std::min<uint64_t>(max, vertex_.count - next_);
    if (encoding_ != Encoding::Ascii && vertex_.fixed() && vertex_.stride() > 0) {  // whole records at once
        const size_t stride = vertex_.stride(), per = std::max<size_t>(1, kChunkBytes / stride);
        std::vector<size_t> at(vertex_.props.size(), 0);
        for (size_t i = 1; i < at.size(); ++i) at[i] = at[i - 1] + sizeOf(vertex_.props[i - 1].type);
        values_.resize(vertex_.props.size());
        for (uint64_t done = 0; done < n;) {
            const size_t m = size_t(std::min<uint64_t>(per, n - done));
            chunk_.resize(m * stride);
            if (!in_.read(reinterpret_cast<char*>(chunk_.data()), std::streamsize(chunk_.size())))
                fail("the file ends inside the vertex element's " + std::to_string(vertex_.count) + " records");
            for (size_t r = 0; r < m; ++r, ++next_, ++done, offset_ += stride) {
                for (size_t i = 0; i < at.size(); ++i)
                    values_[i] = decode(&chunk_[r * stride + at[i]], vertex_.props[i].type, swap_);
                out.push_back(point(values_));
            }
        }
        return out.size();
    }
    for (uint64_t k = 0; k < n; ++k, ++next_) {
        const uint64_t start = offset_;
        const bool ok =
            encoding_ == Encoding::Ascii ? readAsciiRecord(vertex_, values_) : readBinaryRecord(vertex_, values_);
        if (!ok)
            fail("the file ends after " + std::to_string(next_) + " of the vertex element's " +
                 std::to_string(vertex_.count) + " records");
        const uint64_t end = offset_;
        offset_ = start;  // a bad position names its record's start
        out.push_back(point(values_));
        offset_ = end;
    }
    return out.size();
}

void PlyReader::rewind() {
    in_.clear();
    in_.seekg(std::streamoff(vertexOffset_));
    offset_ = vertexOffset_;
    line_ = vertexLine_;
    next_ = 0;
}

}  // namespace

std::unique_ptr<ScanReader> openPly(const std::string& path) { return std::make_unique<PlyReader>(path); }

}  // namespace sg
