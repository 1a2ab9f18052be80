// loadGltf: reads the file (mapped, not copied), checks the bytes, lets tinygltf parse, validates, converts.
#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/gltf/internal/GltfDraco.h"
#include "nodes/Geometry.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>

namespace sg {

static std::string message(const std::string& file, const std::string& path, const std::string& reason) {
    return file + (path.empty() ? "" : ": " + path) + ": " + reason;
}

LoadError::LoadError(std::string file, std::string jsonPath, std::string reason)
    : std::runtime_error(message(file, jsonPath, reason)),
      file_(std::move(file)),
      path_(std::move(jsonPath)),
      reason_(std::move(reason)) {}

namespace gltf {

void Progress::report(double fraction, const char* stage) {
    if (!opt_.progress) return;
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (t < opt_.progressAfterSeconds) return;
    if (fraction < 1.0 && last_ >= 0.0 && t - last_ < 0.1) return;
    last_ = t;
    opt_.progress(std::min(1.0, std::max(0.0, fraction)), stage);
}

namespace {

// A read-only view of a whole file: mapped when possible.
class FileBytes {
public:
    explicit FileBytes(const std::string& path) {
        // Non-blocking: opening a FIFO must not wait for a writer (it is then refused as not regular).
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        if (fd_ < 0) fail(path, "", std::string("cannot open: ") + std::strerror(errno));
        struct stat st {};
        if (::fstat(fd_, &st) != 0) fail(path, "", std::string("cannot stat: ") + std::strerror(errno));
        if (!S_ISREG(st.st_mode)) fail(path, "", "not a regular file");
        size_ = size_t(st.st_size);
        if (size_ == 0) return;
        void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0);
        if (p == MAP_FAILED) fail(path, "", std::string("cannot map: ") + std::strerror(errno));
        data_ = static_cast<const unsigned char*>(p);
    }
    ~FileBytes() {
        if (data_) ::munmap(const_cast<unsigned char*>(data_), size_);
        if (fd_ >= 0) ::close(fd_);
    }
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;
    const unsigned char* data() const { return data_; }
    size_t size() const { return size_; }

private:
    int fd_ = -1;
    const unsigned char* data_ = nullptr;
    size_t size_ = 0;
};

// External files (buffers and images by URI): only regular files, and none for loads from memory (a
// URI such as /dev/zero must not hang a load).
struct FsContext {
    bool allowFiles;
};

// A URI with a scheme (http://, https://, ...) that tinygltf joined to the file's directory, or empty: such a
// buffer or image is on the network, and a load never waits on a server.
std::string networkUri(const std::string& path) {
    const size_t colon = path.find("://");
    if (colon == std::string::npos) return {};
    const size_t slash = path.rfind('/', colon);
    return path.substr(slash == std::string::npos ? 0 : slash + 1);
}
bool isRegularFile(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool fileExists(const std::string& path, void* user) {
    // From memory, or a URL: "exists", so that readWholeFile says why it is not read.
    return !static_cast<FsContext*>(user)->allowFiles || isRegularFile(path) || !networkUri(path).empty();
}
std::string expandPath(const std::string& path, void*) { return path; }
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    if (!static_cast<FsContext*>(user)->allowFiles) {
        if (err) *err += "external file '" + path + "' is not read when loading from memory\n";
        return false;
    }
    if (const std::string uri = networkUri(path); !uri.empty() && !isRegularFile(path)) {
        if (err) *err += "'" + uri + "' is on the network: glTF files are loaded with their local files only\n";
        return false;
    }
    try {
        FileBytes f(path);
        out->assign(f.data(), f.data() + f.size());
        return true;
    } catch (const std::exception& e) {
        if (err) *err += std::string(e.what()) + "\n";
        return false;
    }
}
bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "the loader writes no files\n";
    return false;
}

// Images are decoded after validation (by the conversion, with a size limit): images in a buffer view are
// left alone here (tinygltf hands over their bytes before checking the view lies inside its buffer);
// images by URI keep their encoded bytes.
bool keepEncoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                 int size, void*) {
    if (image->bufferView != -1 || !bytes || size <= 0) return true;
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    size_t b = 0;
    while (b < s.size()) {
        size_t e = s.find('\n', b);
        if (e == std::string::npos) e = s.size();
        if (e > b) out.push_back(s.substr(b, e - b));
        b = e + 1;
    }
    return out;
}

GltfScene load(const std::string& file, const std::string& baseDir, const unsigned char* data, size_t size,
               bool allowFiles, Progress& progress) {
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    prevalidate(file, data, size, binary);
    const std::vector<unsigned char> draco = dracoIndicesForTinygltf(data, size, binary);  // see GltfDraco.h
    if (!draco.empty()) data = draco.data(), size = draco.size();
    progress.report(0.05, "parsing");
    tinygltf::TinyGLTF parser;
    FsContext ctx{allowFiles};
    parser.SetFsCallbacks({&fileExists, &expandPath, &readWholeFile, &writeWholeFile, &ctx});
    parser.SetImageLoader(&keepEncoded, nullptr);
    // The feature extensions' JSON as written: tinygltf's own values cut integers to int (GltfMetadata.h).
    parser.SetStoreOriginalJSONForExtrasAndExtensions(true);
    tinygltf::Model model;
    std::string err, warn;
    auto parse = [&](const unsigned char* bytes, size_t n) {
        try {
            if (binary) return parser.LoadBinaryFromMemory(&model, &err, &warn, bytes, unsigned(n), baseDir);
            return parser.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes), unsigned(n),
                                              baseDir);
        } catch (const std::exception& e) {  // tinygltf lets some std exceptions through (e.g. vector::at)
            fail(file, "", std::string("tinygltf: ") + e.what());
        }
    };
    // JSON that tinygltf refuses or misreads (normalizeForTinygltf): a GLB's, small, is looked at first; a .gltf's,
    // which may hold megabytes of data URIs, when a quick read finds floats for integers or tinygltf has refused it.
    Normalized fixed;
    auto parseFixed = [&]() {
        model = tinygltf::Model();
        err.clear();
        warn.clear();
        return parse(reinterpret_cast<const unsigned char*>(fixed.bytes.data()), fixed.bytes.size());
    };
    const bool first = binary || needsNormalizing(data, size);
    bool ok = first && normalizeForTinygltf(file, data, size, binary, fixed) ? parseFixed() : parse(data, size);
    if (!ok && !first && normalizeForTinygltf(file, data, size, binary, fixed)) ok = parseFixed();
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        fail(file, "", err.empty() ? "tinygltf could not parse it" : err);
    }
    undoNormalizing(fixed, model);
    restorePointerChannels(data, size, binary, model);
    std::vector<std::string> warnings = fixed.warnings;
    for (size_t i = 0; binary && i < model.buffers.size(); ++i)  // allowed; the validator warns
        if (model.buffers[i].uri.rfind("data:", 0) == 0)
            warnings.push_back(at("buffers", i) + ".uri: a data URI inside a GLB, read as in a .gltf");
    for (std::string& w : lines(warn)) warnings.push_back(std::move(w));
    progress.report(0.5, "validating");
    try {
        decodeMeshopt(file, model);
        decodeDraco(file, model);  // compressed primitives become plain accessors before anything reads them
        std::vector<bool> noData = detachMissingData(model);
        validate(file, model);
        applySparse(model);
        return convert(file, model, progress, std::move(warnings), std::move(noData));
    } catch (const std::bad_alloc&) {
        fail(file, "", "out of memory");
    }
}

}  // namespace
}  // namespace gltf

GltfScene loadGltf(const std::string& path, const GltfLoadOptions& options) {
    if (options.generateOccluders) options.occluders.validate("sg::loadGltf()");
    gltf::Progress progress(options);
    progress.report(0.0, "reading");
    gltf::FileBytes bytes(path);
    const size_t slash = path.find_last_of('/');
    const std::string baseDir = slash == std::string::npos ? "" : path.substr(0, slash);
    static const unsigned char empty = 0;
    GltfScene scene = gltf::load(path, baseDir, bytes.size() ? bytes.data() : &empty, bytes.size(), true, progress);
    if (options.generateOccluders && scene.root) generateOccluders(*scene.root, options.occluders);
    return scene;
}

void gltf::workOutSolids(const Node& root) {
    forEachDistinctGeometry(root, [](const Geometry& g) {
        if (g.mesh()) g.mesh()->closed();
    });
}

ref_ptr<Node> loadGltfPage(const std::string& file) {
    ref_ptr<Node> root = loadGltf(file).root;
    if (root) gltf::workOutSolids(*root);
    return root;
}

GltfScene loadGltfFromMemory(const std::string& name, const void* data, size_t size, const GltfLoadOptions& options) {
    if (options.generateOccluders) options.occluders.validate("sg::loadGltfFromMemory()");
    gltf::Progress progress(options);
    static const unsigned char empty = 0;
    GltfScene scene =
        gltf::load(name, "", size ? static_cast<const unsigned char*>(data) : &empty, size, false, progress);
    if (options.generateOccluders && scene.root) generateOccluders(*scene.root, options.occluders);
    return scene;
}

}  // namespace sg
