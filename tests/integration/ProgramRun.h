// ProgramRun: one of the project's programs run as a child process in the running test's own directory (tests
// run in parallel), its exit code and output kept for the test to check.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

// <temp>/<prefix><suite>_<test>: the running test's own directory, created.
inline std::filesystem::path testDirectory(const std::string& prefix) {
    const auto* t = testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / (prefix + t->test_suite_name() + "_" + t->name());
    std::filesystem::create_directories(dir);
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
