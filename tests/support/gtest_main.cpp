/// @file gtest_main.cpp
/// The main of every GoogleTest program of MANTA. CTest runs each test as its own process, many
/// at once (`make test` uses all cores), and several tests of one program write files of the
/// same name under the temporary directory. Each process therefore gets its own temporary
/// directory (TMPDIR, which std::filesystem::temp_directory_path and the child processes a test
/// starts both read), removed at the end when every test passed and kept for inspection when one
/// failed.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    const fs::path base = fs::temp_directory_path();
    const fs::path own = base / ("manta-test-" + std::to_string(::getpid()));
    std::error_code ec;
    fs::create_directories(own, ec);
    const bool isolated = !ec && ::setenv("TMPDIR", own.c_str(), 1) == 0;
    ::testing::InitGoogleTest(&argc, argv);
    const int rc = RUN_ALL_TESTS();
    if (isolated) {
        if (rc == 0)
            fs::remove_all(own, ec);
        else
            std::cerr << "test files kept in " << own.string() << "\n";
    }
    return rc;
}
