// The main of every test executable. ctest runs the tests of one executable as separate processes side by side,
// and many write files under gtest's TempDir() by a name of their own (a glb, a tileset): in a shared /tmp two
// processes wrote and read the same file, one truncating a glb while another read it. Each process gets its own
// directory (gtest's TempDir() reads TEST_TMPDIR; children inherit it), removed when every test passed and kept,
// its path printed, when one failed, for the images and files a failure leaves.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

int main(int argc, char** argv) {
    const std::string pattern = ::testing::TempDir() + "sgkit_test_XXXXXX";
    std::vector<char> dir(pattern.begin(), pattern.end());
    dir.push_back('\0');
    if (!mkdtemp(dir.data())) {
        std::fprintf(stderr, "cannot make a temporary directory %s: %s\n", pattern.c_str(), std::strerror(errno));
        return 1;
    }
    setenv("TEST_TMPDIR", dir.data(), 1);
    ::testing::InitGoogleTest(&argc, argv);
    const int failed = RUN_ALL_TESTS();
    if (failed) {
        std::fprintf(stderr, "files the tests wrote are kept in %s\n", dir.data());
    } else {
        std::error_code ignored;
        std::filesystem::remove_all(dir.data(), ignored);
    }
    return failed;
}
