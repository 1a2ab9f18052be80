#include "common/WindowProgram.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

namespace common {

int runWindowProgram(char** argv, const char* program, const char* self, const char* withoutWindow) {
    if (!program) {
        std::fprintf(stderr, "%s: %s\n", self, withoutWindow);
        return 2;
    }
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string path = ((ec ? std::filesystem::path(argv[0]) : exe).parent_path() / program).string();
    argv[0] = const_cast<char*>(path.c_str());
    execv(path.c_str(), argv);
    std::fprintf(stderr, "%s: cannot start the window program %s: %s\n", self, path.c_str(), std::strerror(errno));
    return 1;
}

}  // namespace common
