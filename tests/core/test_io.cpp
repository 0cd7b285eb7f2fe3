// Tests of src/core/io.cpp: CSV parsing and its located errors, atomic writes, exact number text.
#include <gtest/gtest.h>

#include <unistd.h>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace {

namespace fs = std::filesystem;
using manta::core::format_exact;
using manta::core::parse_csv;

std::string input_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected InputError, nothing thrown";
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

/// A fresh empty folder under the system temporary folder.
fs::path scratch(const std::string& name) {
    const fs::path p =
        fs::temp_directory_path() / ("manta_io_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// ------------------------------------------------------------------------------------ CSV

TEST(Csv, ParsesHeaderRowsCommentsAndWhitespace) {
    const auto t = parse_csv(
        "# made by a test\n t , V,alpha \n\n0, 150.5 ,1e-2\r\n# mid comment\n1,+151,-0.5\n",
        "in.csv");
    ASSERT_EQ(t.columns.size(), 3u);
    EXPECT_EQ(t.columns[0], "t");
    EXPECT_EQ(t.columns[2], "alpha");
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_DOUBLE_EQ(t.rows[0][1], 150.5);
    EXPECT_DOUBLE_EQ(t.rows[0][2], 0.01);
    EXPECT_DOUBLE_EQ(t.rows[1][1], 151.0);
    EXPECT_EQ(t.row_lines[0], 4);
    EXPECT_EQ(t.row_lines[1], 6);
    ASSERT_EQ(t.comments.size(), 2u);
    EXPECT_EQ(t.comments[0], "made by a test");
    EXPECT_EQ(t.find("V"), 1);
    EXPECT_EQ(t.find("beta"), -1);
    EXPECT_EQ(t.require("alpha"), 2u);
    EXPECT_EQ(t.column(0), (std::vector<double>{0.0, 1.0}));
}

TEST(CsvErrors, NonNumericField) {
    const auto msg = input_error([] { (void)parse_csv("a,b\n1,2\n3,x\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:3", "column 'b'", "value 'x'", "is not a number"});
}

TEST(CsvErrors, EmptyField) {
    const auto msg = input_error([] { (void)parse_csv("a,b\n1,\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:2", "column 'b'", "is not a number"});
}

TEST(CsvErrors, NumberWithTrailingText) {
    const auto msg = input_error([] { (void)parse_csv("a\n1.5m\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:2", "column 'a'", "value '1.5m'", "is not a number"});
}

TEST(CsvErrors, NonFiniteField) {
    for (const char* bad : {"inf", "nan", "-inf"}) {
        const auto msg =
            input_error([&] { (void)parse_csv(std::string("a,b\n1,") + bad + "\n", "traj.csv"); });
        expect_parts(msg, {"traj.csv:2", "column 'b'", std::string("value '") + bad + "'",
                           "is not finite", "expected a finite number"});
    }
}

TEST(CsvErrors, RowOfWrongLength) {
    const auto msg = input_error([] { (void)parse_csv("a,b,c\n1,2,3\n\n1,2\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:4", "row has 2 fields", "expected 3 as in the header"});
}

TEST(CsvErrors, EmptyHeaderColumn) {
    const auto msg = input_error([] { (void)parse_csv("# c\na,,c\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:2", "column 2 of the header is empty"});
}

TEST(CsvErrors, DuplicatedColumn) {
    const auto msg = input_error([] { (void)parse_csv("t,x,t\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv:1", "column 't' appears twice"});
}

TEST(CsvErrors, NoHeader) {
    const auto msg = input_error([] { (void)parse_csv("# only comments\n\n", "traj.csv"); });
    expect_parts(msg, {"traj.csv", "no header line", "comma-separated column names"});
}

TEST(CsvErrors, MissingRequiredColumn) {
    const auto t = parse_csv("t,x\n0,1\n", "traj.csv");
    const auto msg = input_error([&] { (void)t.require("alpha"); });
    expect_parts(msg, {"traj.csv", "missing column 'alpha'", "columns present: t, x"});
}

TEST(CsvErrors, FileMissing) {
    EXPECT_THROW((void)manta::core::read_csv("/nonexistent/traj.csv"), manta::IoError);
}

TEST(Csv, WriteReadRoundTripIsExact) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1e3, 1e3);
    std::vector<std::vector<double>> rows;
    for (int i = 0; i < 50; ++i) rows.push_back({u(rng), u(rng) * 1e-9, u(rng) * 1e12});
    rows.push_back({0.1, -0.0, 1.0 / 3.0});
    const std::string text = manta::core::to_csv({"a", "b", "c"}, rows, {"written by a test"});
    const auto t = parse_csv(text, "round.csv");
    EXPECT_EQ(t.comments, (std::vector<std::string>{"written by a test"}));
    ASSERT_EQ(t.rows.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t j = 0; j < 3; ++j) EXPECT_EQ(t.rows[i][j], rows[i][j]) << i << "," << j;
}

// ------------------------------------------------------------------------------------ files

TEST(Files, AtomicWriteCreatesFoldersAndLeavesNoTemporary) {
    const fs::path dir = scratch("atomic");
    const fs::path file = dir / "a" / "b" / "result.txt";
    manta::core::write_file_atomic(file, "first\n");
    EXPECT_EQ(manta::core::read_file(file), "first\n");
    manta::core::write_file_atomic(file, std::string("second\0with nul", 15));
    EXPECT_EQ(manta::core::read_file(file), std::string("second\0with nul", 15));
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(file.parent_path())) {
        ++n;
        EXPECT_EQ(e.path().filename(), "result.txt");
    }
    EXPECT_EQ(n, 1u);
    fs::remove_all(dir);
}

TEST(Files, AtomicWriteKeepsTheOldFileWhenItCannotWrite) {
    const fs::path dir = scratch("blocked");
    // The target is an existing non-empty directory: rename cannot replace it.
    const fs::path target = dir / "out";
    fs::create_directories(target / "inside");
    try {
        manta::core::write_file_atomic(target, "data");
        FAIL() << "no error";
    } catch (const manta::IoError& e) {
        EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_directory(target / "inside"));
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename(), "out") << "temporary left behind";
    fs::remove_all(dir);
}

TEST(Files, AtomicWriteUnderAFileFails) {
    const fs::path dir = scratch("underfile");
    manta::core::write_file_atomic(dir / "plain", "x");
    EXPECT_THROW(manta::core::write_file_atomic(dir / "plain" / "child.txt", "y"), manta::IoError);
    fs::remove_all(dir);
}

TEST(Files, ReadMissingFileAndDirectory) {
    try {
        (void)manta::core::read_file("/nonexistent/file.txt");
        FAIL() << "no error";
    } catch (const manta::IoError& e) {
        expect_parts(e.what(), {"/nonexistent/file.txt", "cannot open"});
    }
    EXPECT_THROW((void)manta::core::read_file(fs::temp_directory_path()), manta::IoError);
}

// ------------------------------------------------------------------------------------ exact text

double parse_back(const std::string& s) {
    double v = 0.0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    EXPECT_EQ(r.ptr, s.data() + s.size()) << s;
    return v;
}

TEST(FormatExact, RoundTripsEveryFiniteDouble) {
    const std::vector<double> special{0.0,
                                      -0.0,
                                      0.1,
                                      1.0 / 3.0,
                                      -2.5e-300,
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::lowest(),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::epsilon(),
                                      std::nextafter(1.0, 2.0),
                                      14190.0,
                                      9.80665};
    for (double v : special) {
        const std::string s = format_exact(v);
        EXPECT_EQ(parse_back(s), v) << s;
        EXPECT_EQ(std::signbit(parse_back(s)), std::signbit(v)) << s;
    }
    // Random bit patterns cover every exponent, subnormals included.
    std::mt19937_64 rng(7);
    int tested = 0;
    while (tested < 20000) {
        const std::uint64_t bits = rng();
        double v;
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isfinite(v)) continue;
        ++tested;
        const std::string s = format_exact(v);
        EXPECT_EQ(parse_back(s), v) << s;
    }
}

TEST(FormatExact, IsShortest) {
    EXPECT_EQ(format_exact(0.1), "0.1");
    EXPECT_EQ(format_exact(15.5), "15.5");
    EXPECT_EQ(format_exact(14190.0), "14190");
    EXPECT_EQ(format_exact(-0.0), "-0");
}

}  // namespace
