// Built-in scenes, and the checks every file passes before the loader sees it.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/build/GeneratedOccluders.h"
#include "sg/gl/Renderer.h"
#include "sgview/LoadScene.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/Figure.h"
#include "testbed/Materials.h"
#include "testbed/Office.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace sgview {

#ifdef SGVIEW_NO_GLTF
LoadedScene loadSceneFile(const std::string& path, const Options&) {
    throw UsageError(
        "'" + path +
        "': sgview was built without the glTF loader (sgkit::loaders); --scene city|office|factory|materials works");
}
sg::FeatureStyle::Rule loadStyleFile(const std::string& path) {
    throw UsageError("--style '" + path + "': sgview was built without the loaders (sgkit::loaders)");
}
void saveSceneFile(const LoadedScene&, const std::string& path) {
    throw UsageError("--save '" + path + "': sgview was built without the glTF loader (sgkit::loaders)");
}
#endif

namespace {

void checkReadable(const std::string& path) {
    if (path.rfind("http://", 0) == 0 || path.rfind("https://", 0) == 0) return;  // a tileset's URL: read later
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) throw UsageError("'" + path + "': no such file");
    if (std::filesystem::is_directory(st)) throw UsageError("'" + path + "': is a directory, not a glTF file");
    if (!std::ifstream(path, std::ios::binary)) throw UsageError("'" + path + "': cannot be opened for reading");
}

}  // namespace

namespace {
LoadedScene loadSources(const Options& o);
}  // namespace

// --auto-occluders: occluders made from the geometry, what was made said among the warnings (a tileset's tiles make
// theirs as they are read: loadSceneFile).
LoadedScene loadScene(const Options& o) {
    LoadedScene s = loadSources(o);
    if (!o.style.empty()) {
        try {
            s.styleRule = loadStyleFile(o.style);
        } catch (const UsageError&) {
            throw;
        } catch (const std::exception& e) {  // sg::LoadError names the file, the JSON path and the expression
            throw UsageError(std::string("--style: ") + e.what());
        }
    }
    if (!o.autoOccluders || !s.root) return s;
    if (s.pageLoad) {
        s.warnings.push_back("--auto-occluders: made in each tile as it is read");
        return s;
    }
    const sg::OccluderGenStats st = sg::generateOccluders(*s.root);
    char line[256];
    std::snprintf(line, sizeof line,
                  "--auto-occluders: %llu boxes and %llu polygons for %llu geometries (%llu meshes, %llu triangles) in "
                  "%.1f ms",
                  (unsigned long long)st.boxes, (unsigned long long)st.polygons, (unsigned long long)st.geometries,
                  (unsigned long long)st.meshes, (unsigned long long)st.meshTriangles, st.ms);
    s.warnings.push_back(line);
    return s;
}

namespace {
LoadedScene loadSources(const Options& o) {
    const std::string size = std::to_string(o.n) + "x" + std::to_string(o.n);
    if (o.scene == "city") return {scenes::buildCity({o.n, false, true}), {}, {0.0, 0.0, 1.0}, "city " + size};
    if (o.scene == "office") return {scenes::buildOffice(o.n), {}, {0.0, 0.0, 1.0}, "office " + size};
    if (o.scene == "materials") return {scenes::buildMaterials(), {}, {0.0, 1.0, 0.0}, "materials"};
    if (o.scene == "figures") {
        LoadedScene s{sg::make<sg::Group>(), {}, {0.0, 1.0, 0.0}, "figures " + size};
        auto* root = static_cast<sg::Group*>(s.root.get());
        root->addChild(
            scenes::makeCrowd(o.n * o.n, sg::dvec3(-0.8 * (o.n - 1), 0.0, -0.8 * (o.n - 1)), o.n, 1.6, s.animations));
        // The ground's top below the lowest a foot reaches: no depth ties where a foot meets it.
        root->addChild(sg::make<sg::Geometry>(sg::makeBoxMesh(sg::dvec3(-0.8 * o.n - 1, -0.12, -0.8 * o.n - 1),
                                                              sg::dvec3(0.8 * o.n + 1, -0.06, 0.8 * o.n + 1)),
                                              sg::make<sg::Material>(sg::vec4(0.45f, 0.5f, 0.45f, 1.0f))));
        return s;
    }
    if (o.scene == "factory") return {scenes::buildFactory().root, {}, {0.0, 0.0, 1.0}, "factory"};
    for (const std::string& f : o.files) checkReadable(f);  // every file before the first (slow) load
    auto load = [&o](const std::string& f) {
        try {
            return loadSceneFile(f, o);
        } catch (const UsageError&) {
            throw;
        } catch (const std::exception& e) {  // sg::LoadError names the file, the JSON path and the reason
            throw UsageError(e.what());
        }
    };
    if (o.files.size() == 1) return load(o.files[0]);
    LoadedScene all;
    auto root = sg::make<sg::Group>();
    for (const std::string& f : o.files) {
        LoadedScene one = load(f);
        if (one.pageLoad) throw UsageError("'" + f + "': a tileset is shown alone, not with other files");
        root->addChild(one.root);
        for (std::string& w : one.warnings) all.warnings.push_back(f + ": " + w);
        all.up = one.up;
        for (const sg::PunctualLight& l : one.lights)
            if (all.lights.size() < sg::Renderer::kMaxLights) all.lights.push_back(l);
    }
    all.root = root;
    all.title = std::to_string(o.files.size()) + " files";
    return all;
}

}  // namespace

}  // namespace sgview
