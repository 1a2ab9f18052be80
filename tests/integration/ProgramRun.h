// ProgramRun: one of the project's programs run as a child process in the running test's own directory (tests
// run in parallel), its exit code and output kept for the test to check.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

struct ProgramRun {
    int code = -1;  // exit code; 128 + signal when killed (a crash)
    std::string out, err;
};

inline std::string slurpFile(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// The test directories of this process: removed when it ends, unless a test failed (kept to look at).
struct TestDirectories {
    std::vector<std::filesystem::path> dirs;
    ~TestDirectories() {
        if (testing::UnitTest::GetInstance()->failed_test_count() > 0) return;
        std::error_code ec;
        for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
    }
};
inline TestDirectories& testDirectories() {
    static TestDirectories all;
    return all;
}

// <temp>/<prefix><suite>_<test>_<pid>: the running test's own directory, created. The process id keeps two
// runs of the same test (two build trees, a rerun while one still runs) out of each other's files.
inline std::filesystem::path testDirectory(const std::string& prefix) {
    const auto* t = testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        (prefix + t->test_suite_name() + "_" + t->name() + "_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    testDirectories().dirs.push_back(dir);
    return dir;
}

// Runs `command` with the shell in `dir`; its output goes to out.txt and err.txt there.
inline ProgramRun runProgram(const std::filesystem::path& dir, const std::string& command) {
    const int status = std::system(("cd '" + dir.string() + "' && " + command + " > out.txt 2> err.txt").c_str());
    ProgramRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurpFile(dir / "out.txt");
    r.err = slurpFile(dir / "err.txt");
    return r;
}

// `xvfb-run -n N -a` for this test: a virtual X server whose display number is searched from a start of the
// test's own. Plain -a starts every search at :99, and xvfb-runs started together can take the same number (one
// window then fails to open its display); searches starting far apart do not meet.
inline std::string xvfbRun(const char* xvfbRunPath) {
    const auto* t = testing::UnitTest::GetInstance()->current_test_info();
    const size_t h = std::hash<std::string>{}(std::string(t->test_suite_name()) + "." + t->name());
    const int start = 200 + int((h + size_t(getpid()) * 7919u) % 5000u);
    return "'" + std::string(xvfbRunPath) + "' -n " + std::to_string(start) + " -a -s '-screen 0 1024x768x24'";
}
