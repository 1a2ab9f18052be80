// sgbench's shared pieces: argument parsing, JSON output, timing and memory readings.
#pragma once
#include "sg/build/PvsBuilder.h"
#include "sg/core/Camera.h"
#include "sg/core/Node.h"
#include "testbed/Stats.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace bench {

struct Args {
    std::string command;
    std::map<std::string, std::string> opts;  // --key value, or --flag -> "1"
    // Throws std::invalid_argument naming the option when a value is missing or not a number.
    std::string str(const std::string& key, const std::string& def) const;
    long num(const std::string& key, long def) const;
    bool flag(const std::string& key) const { return opts.count(key) != 0; }
};
Args parseArgs(int argc, char** argv);

// One flat JSON object, keys in insertion order.
class Json {
public:
    Json& add(const std::string& k, double v);
    Json& add(const std::string& k, const std::string& v);
    Json& addInt(const std::string& k, long long v);
    std::string str() const;
    // Human-readable table of the same fields.
    std::string table() const;
    // To stdout: one JSON line with --json, else "sgbench <command>" and the table.
    void print(const Args& a) const;

private:
    std::vector<std::pair<std::string, std::string>> kv_;
};

double rssMb();
// Resident memory by what holds it (MemoryParts.cpp). otherAnonMb: anonymous memory malloc does not account for
// (llvmpipe's maps, JIT code); negative when malloc keeps freed memory that is not resident.
struct MemoryParts {
    double totalMb = 0.0, heapLiveMb = 0.0, heapFreeMb = 0.0, otherAnonMb = 0.0, filesMb = 0.0, stacksMb = 0.0;
};
MemoryParts memoryParts();
// The parts as "<prefix>_total_mb", "<prefix>_heap_live_mb" and so on.
void addMemoryParts(Json& j, const std::string& prefix, const MemoryParts& p);
// The bytes malloc has handed out and not had back (mallinfo2): what is live, apart from what a process keeps freed.
double heapMb();
using stats::median;  // testbed/Stats.h: the same definitions as bench/osg_peer's, which compare_osg.sh divides by
using stats::percentile;

int runCull(const Args& a);
int runAccuracy(const Args& a);
int runOcclusion(const Args& a);
int runLod(const Args& a);
int runPick(const Args& a);
// sgbench pick --features: picks that read the hit's features against bare picks (PickFeaturesBench.cpp).
int runPickFeatures(const Args& a);
int runLoad(const Args& a);
// sgbench load --features: a tile with a property table against the same without (LoadFeaturesBench.cpp).
int runLoadFeatures(const Args& a);
int runPvs(const Args& a);
int runTerrain(const Args& a);
int runPcvr(const Args& a);
int runPareto(const Args& a);
int runDepth(const Args& a);
int runTiles(const Args& a);
int runFrame(const Args& a);
int runStyle(const Args& a);
// sgbench points: points drawn at 1 px, 3 px discs and with eye-dome lighting, beside triangles (PointsBench.cpp).
int runPoints(const Args& a);
// sgbench motion: a crowd of skinned walking figures in the city, moving against frozen (MotionBench.cpp).
int runMotion(const Args& a);
// sgbench variants: a material never drawn before shown each frame, its shader variants compiled in the frame or
// prepared before the first (VariantsBench.cpp).
int runVariants(const Args& a);
// The PVS grid around city's street path (n) or office's walk (n rooms a side), computed only at the
// cameras' eyes, for their near planes.
sg::PvsBuilder::Options pvsPathOptions(bool city, int n, const std::vector<sg::Camera>& cams);
// Every LOD level below `n` given geometric error 0: the city's two levels are the same box (sgbench lod, pareto).
void setLevelErrorsToZero(sg::Node& n);

}  // namespace bench
