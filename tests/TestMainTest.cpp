// The tests' main (TestMain.cpp): each test process writes its files in a temporary directory of its own, so that
// tests ctest runs side by side never share a file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

TEST(TestMain, EachProcessWritesInATemporaryDirectoryOfItsOwn) {
    const std::string dir = ::testing::TempDir();
    EXPECT_NE(dir.find("sgkit_test_"), std::string::npos) << dir;  // not the shared /tmp/
    EXPECT_TRUE(std::filesystem::is_directory(dir)) << dir;
    const char* env = std::getenv("TEST_TMPDIR");  // what child processes inherit
    ASSERT_NE(env, nullptr);
    EXPECT_EQ(dir.rfind(env, 0), 0u) << dir << " against " << env;
}
