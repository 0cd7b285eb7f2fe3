/// @file test_process.cpp
/// core/process.hpp: a command's exit status, log and last line; a command that cannot start;
/// the environment added; the shell-like splitting of a launcher command line.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "manta/core/error.hpp"
#include "manta/core/process.hpp"

namespace {

namespace fs = std::filesystem;
using manta::core::run_process;
using manta::core::split_command;

fs::path scratch() {
    const fs::path d = fs::temp_directory_path() / ("manta-process-" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
}

TEST(Process, ExitStatusLogAndLastLine) {
    const fs::path log = scratch() / "sub" / "a.log";
    fs::remove(log);
    const auto ok = run_process({"sh", "-c", "echo first; echo last; echo oops >&2; exit 0"}, log);
    EXPECT_EQ(ok.exit_code, 0);
    EXPECT_EQ(ok.last_line, "oops");
    const auto bad = run_process({"sh", "-c", "echo failing; exit 3"}, log);
    EXPECT_EQ(bad.exit_code, 3);
    EXPECT_EQ(bad.last_line, "failing");  // appended to the same log
    std::ifstream in(log);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(all.find("first\nlast\n"), std::string::npos) << all;
}

TEST(Process, SignalEnvironmentAndACommandThatCannotStart) {
    const fs::path log = scratch() / "b.log";
    EXPECT_EQ(run_process({"sh", "-c", "kill -9 $$"}, log).exit_code, 128 + 9);
    const auto env =
        run_process({"sh", "-c", "echo \"v=$MANTA_TEST_VALUE\""}, log, {"MANTA_TEST_VALUE=42"});
    EXPECT_EQ(env.last_line, "v=42");
    try {
        (void)run_process({"manta-no-such-program-xyz"}, log);
        FAIL() << "no error";
    } catch (const manta::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot start 'manta-no-such-program-xyz'"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW((void)run_process({}, log), manta::IoError);
}

TEST(Process, SplitCommandAsAShellWithoutExpansions) {
    using V = std::vector<std::string>;
    EXPECT_EQ(split_command("mpirun -np 4", "x"), (V{"mpirun", "-np", "4"}));
    EXPECT_EQ(split_command("  srun\t-n 64  ", "x"), (V{"srun", "-n", "64"}));
    EXPECT_EQ(split_command("a 'b c' \"d \\\"e\\\"\" f\\ g", "x"),
              (V{"a", "b c", "d \"e\"", "f g"}));
    EXPECT_EQ(split_command("pre'fix'\"ed\"", "x"), (V{"prefixed"}));
    EXPECT_EQ(split_command("a '' b", "x"), (V{"a", "", "b"}));
    EXPECT_TRUE(split_command("", "x").empty());
    try {
        (void)split_command("mpirun 'np", "campaign.yaml:3: launcher");
        FAIL() << "no error";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("campaign.yaml:3: launcher"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("unterminated single quote"), std::string::npos);
    }
    EXPECT_THROW((void)split_command("x \"y", "w"), manta::InputError);
}

}  // namespace
