#include "factory/Options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace factory {

namespace {
std::string value(int argc, char** argv, int& i) {
    const std::string name = argv[i];
    if (i + 1 >= argc) throw OptionError(name + " needs a value");
    return argv[++i];
}
long integer(const std::string& name, const std::string& v, long lo, long hi) {
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || x < lo || x > hi)
        throw OptionError(name + " '" + v + "' is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return x;
}
}  // namespace

const char* usage() {
    return "usage: factory [--headless] [--frames N] [--size WxH] [--budget-ms MS] [--out-dir DIR] [--json]\n"
           "               [--cache-dir DIR] [--no-lighting] [--background-load none|spin]\n";
}

Options parseOptions(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        if (k == "--headless") {
            o.headless = true;
        } else if (k == "--json") {
            o.json = true;
        } else if (k == "--frames") {
            o.frames = int(integer(k, value(argc, argv, i), 10, 100000));
        } else if (k == "--size") {
            const std::string v = value(argc, argv, i);
            int w = 0, h = 0;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
                throw OptionError("--size '" + v + "' is not WxH with both in 16..8192");
            o.width = w;
            o.height = h;
        } else if (k == "--budget-ms") {
            const std::string v = value(argc, argv, i);
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(x) || x < 1.0 || x > 10000.0)
                throw OptionError("--budget-ms '" + v + "' is not a number of milliseconds in 1..10000");
            o.budgetMs = x;
        } else if (k == "--out-dir") {
            o.outDir = value(argc, argv, i);
            if (o.outDir.empty()) throw OptionError("--out-dir is empty");
        } else if (k == "--cache-dir") {
            o.cacheDir = value(argc, argv, i);
            if (o.cacheDir.empty()) throw OptionError("--cache-dir is empty");
        } else if (k == "--no-lighting") {
            o.lighting = false;
        } else if (k == "--background-load") {
            const std::string v = value(argc, argv, i);
            try {
                o.backgroundLoad = scenes::BackgroundLoad::parse(v);
            } catch (const std::invalid_argument&) {
                throw OptionError("--background-load '" + v + "' is not none or spin");
            }
        } else if (k == "--jitter-draws") {
            o.jitterDraws = int(integer(k, value(argc, argv, i), 2, 10000));
        } else {
            throw OptionError("unknown option '" + k + "'");
        }
    }
    return o;
}

}  // namespace factory
