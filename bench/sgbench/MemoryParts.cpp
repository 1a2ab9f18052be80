// The process's resident memory by what holds it, from /proc/self/smaps and malloc's own figures (mallinfo2), so
// that a flight's peak can be told apart: what the program holds, what malloc keeps freed, what the libraries'
// files map (LLVM, Mesa), and the other anonymous maps (llvmpipe's scenes and JIT code, thread stacks).
#include "sgbench/Bench.h"

#include <malloc.h>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>

namespace bench {

MemoryParts memoryParts() {
    MemoryParts p;
    std::ifstream f("/proc/self/smaps");
    std::string line, path;
    double anonKb = 0.0, fileKb = 0.0, stackKb = 0.0;
    while (std::getline(f, line)) {
        if (!line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) && line.find('-') < 16) {
            std::istringstream h(line);
            std::string range, perms, offset, dev, inode;
            h >> range >> perms >> offset >> dev >> inode;
            path.clear();
            std::getline(h >> std::ws, path);
        } else if (line.compare(0, 4, "Rss:") == 0) {
            const double kb = std::stod(line.substr(4));
            if (path.compare(0, 6, "[stack") == 0)
                stackKb += kb;
            else if (!path.empty() && path[0] == '/')
                fileKb += kb;
            else
                anonKb += kb;  // [heap], thread arenas, large allocations, llvmpipe's maps
        }
    }
    const struct mallinfo2 m = mallinfo2();
    p.heapLiveMb = double(m.uordblks + m.hblkhd) / (1 << 20);
    p.heapFreeMb = double(m.fordblks) / (1 << 20);  // freed, kept by malloc (some of it may not be resident)
    p.filesMb = fileKb / 1024.0;
    p.stacksMb = stackKb / 1024.0;
    p.otherAnonMb = anonKb / 1024.0 - p.heapLiveMb - p.heapFreeMb;
    p.totalMb = (anonKb + fileKb + stackKb) / 1024.0;
    return p;
}

void addMemoryParts(Json& j, const std::string& prefix, const MemoryParts& p) {
    j.add(prefix + "_total_mb", p.totalMb).add(prefix + "_heap_live_mb", p.heapLiveMb);
    j.add(prefix + "_heap_free_mb", p.heapFreeMb).add(prefix + "_other_anon_mb", p.otherAnonMb);
    j.add(prefix + "_files_mb", p.filesMb).add(prefix + "_stacks_mb", p.stacksMb);
}

}  // namespace bench
