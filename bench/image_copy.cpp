// image_copy: what a cull beside the application costs the update, against a double-buffered image.
//
// With the cull of frame N running while the application changes the graph for frame N+1, the image the cull reads
// must not change under it. sgkit copies into the image, at Scene::update(), what the application changes per frame
// (switch bits, masks, general matrices), and updates only between culls. Performer's alternative (pfBuffer) gives
// each stage its own copy of the data: here, a copy of the whole FlatImage per frame. This prints, for the factory
// and the city (N = 316 and 1000 by default), the median time of an update after one Switch turned and after one
// general Transform moved, beside the time to copy-construct the scene's image.
//
//     image_copy [city sizes...]
#include "nodes/Geometry.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/scene/Scene.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/Stats.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

using namespace sg;

namespace {

double medianMs(int runs, const std::function<void()>& setup, const std::function<void()>& timed) {
    std::vector<double> ms;
    for (int r = 0; r < runs; ++r) {
        setup();
        const auto t0 = std::chrono::steady_clock::now();
        timed();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return stats::median(ms);
}

void measure(const std::string& name, Scene& scene, Switch& sw, Transform& t, int runs) {
    scene.update();
    const dmat4 at = t.matrix();
    int k = 0;
    const double unchanged = medianMs(
        runs, [] {}, [&] { scene.update(); });
    const uint64_t v0 = scene.version();
    const double turn = medianMs(
        runs, [&] { sw.setAll(++k % 2 == 0); }, [&] { scene.update(); });
    const int turned = int(scene.version() - v0);  // the updates that saw a turn (not the first when it was off)
    const double move = medianMs(
        runs, [&] { t.setMatrix(glm::rotate(at, 0.01 * double(++k % 100 + 1), dvec3(0, 0, 1))); },
        [&] { scene.update(); });
    size_t entries = 0;
    const double copy = medianMs(
        runs, [] {},
        [&] {
            const FlatImage copied(scene.image());
            entries = copied.size();
        });
    std::printf(
        "%-10s entries %9zu  image %8.1f MB  update: unchanged %.4f ms, switch turned %.4f ms (%d of %d turned), "
        "general transform moved %.4f ms  |  image copy %.3f ms\n",
        name.c_str(), entries, double(scene.image().bytes()) / 1e6, unchanged, turn, turned, runs, move, copy);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    for (int i = 1; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
    if (sizes.empty()) sizes = {316, 1000};
    {
        scenes::Factory f = scenes::buildFactory();
        Scene scene(f.root);
        measure("factory", scene, *f.workshops[0].interior, *f.buildings[0].place, 51);
    }
    for (int n : sizes) {
        ref_ptr<Group> city = scenes::buildCity({n, false});
        // A Switch and a general Transform in a tile in the middle of the city, each over one building's box.
        Group& tile = static_cast<Group&>(*city->child(city->numChildren() / 2));
        auto sw = make<Switch>();
        sw->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1)), make<Material>()));
        const dvec3 at = static_cast<const Transform&>(*tile.child(0)->child(0)).translation();
        auto t = make<Transform>(glm::rotate(glm::translate(dmat4(1.0), at), 0.3, dvec3(0, 0, 1)));
        t->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1)), make<Material>()));
        tile.addChild(sw);
        tile.addChild(t);
        Scene scene(city);
        measure("city " + std::to_string(n), scene, *sw, *t, n >= 1000 ? 15 : 31);
    }
    return 0;
}
