// Which animations sgview plays (--animation), and from when (--time).
#include "sgview/LoadScene.h"

#include <cstdio>

namespace sgview {

std::string startAnimations(sg::AnimationPlayer& player, const LoadedScene& scene, const Options& o) {
    if (scene.animations.empty()) {
        if (!o.animation.empty()) throw UsageError("--animation " + o.animation + ": the scene has no animations");
        return {};
    }
    std::vector<size_t> chosen;
    for (const auto& a : scene.animations) player.add(a);
    if (o.animation == "all") {
        for (size_t i = 0; i < player.size(); ++i) chosen.push_back(i);
    } else if (o.animation.empty()) {
        chosen.push_back(0);
    } else {
        const int i = player.find(o.animation);
        if (i < 0) {
            std::string names;
            for (size_t k = 0; k < player.size(); ++k)
                names += (k ? ", " : "") + std::to_string(k) + " '" + player.animation(k).name + "'";
            throw UsageError("--animation " + o.animation + ": no such animation (the scene has " + names + ")");
        }
        chosen.push_back(size_t(i));
    }
    // The built-in figures walk together: every walk is one figure's.
    if (o.animation.empty() && !o.scene.empty())
        for (size_t i = 1; i < player.size(); ++i) chosen.push_back(i);
    for (size_t i : chosen) {
        player.play(i);
        player.seek(i, o.time);
    }
    if (o.headless) player.pauseAll(true);  // the pose at --time, whatever the frames take
    char line[256];
    std::snprintf(line, sizeof line, "%s %zu of %zu animation%s ('%s', %.2f s)%s at %.2f s",
                  o.headless ? "posed" : "playing", chosen.size(), player.size(), player.size() == 1 ? "" : "s",
                  player.animation(chosen[0]).name.c_str(), player.animation(chosen[0]).duration(),
                  chosen.size() > 1 ? " and others" : "", o.time);
    return line;
}

}  // namespace sgview
