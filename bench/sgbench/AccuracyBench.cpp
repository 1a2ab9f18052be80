#include "sgbench/Bench.h"
namespace bench {
int runAccuracy(const Args&) { return 2; }
}
