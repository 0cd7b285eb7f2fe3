// Tests of src/core/io.cpp: CSV parsing and its located errors, atomic writes, exact number text,
// output folders (checked, locked), leftover temporaries; of the message escaping (text.cpp,
// error.cpp).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/text.hpp"

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

/// A process id that belonged to a process of ours that has ended (and been reaped).
pid_t dead_pid() {
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return pid;
}

/// The IoError message of `f`, or a failure.
std::string io_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::IoError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected IoError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected IoError, nothing thrown";
    return {};
}

TEST(Files, TemporariesOfEndedProcessesAreRemovedByTheNextWriter) {
    // A process killed while writing leaves NAME.tmpPID; the next writer in the folder removes
    // it when PID is no longer alive, and keeps a live process's temporary.
    const fs::path dir = scratch("stale");
    const std::string dead = std::to_string(dead_pid());
    const std::string alive = std::to_string(::getppid());
    for (const std::string& name :
         std::vector<std::string>{"result.csv.tmp" + dead, "other.csv.tmp" + dead,
                                  "result.csv.tmp" + alive, "notes.tmpx", "data.csv"})
        std::ofstream(dir / name) << "x";
    manta::core::write_file_atomic(dir / "result.csv", "new\n");
    EXPECT_FALSE(fs::exists(dir / ("result.csv.tmp" + dead)));
    EXPECT_FALSE(fs::exists(dir / ("other.csv.tmp" + dead)));
    EXPECT_TRUE(fs::exists(dir / ("result.csv.tmp" + alive)));
    EXPECT_TRUE(fs::exists(dir / "notes.tmpx"));
    EXPECT_TRUE(fs::exists(dir / "data.csv"));
    EXPECT_EQ(manta::core::read_file(dir / "result.csv"), "new\n");
    fs::remove_all(dir);
}

TEST(Files, StaleTemporariesBelowARunFolder) {
    const fs::path dir = scratch("stale_tree");
    const std::string dead = std::to_string(dead_pid());
    fs::create_directories(dir / "a" / "b");
    std::ofstream(dir / "a" / "b" / ("plot.svg.tmp" + dead)) << "x";
    std::ofstream(dir / ("summary.json.tmp" + dead)) << "x";
    EXPECT_EQ(manta::core::remove_stale_temporaries(dir, false), 1u);
    EXPECT_TRUE(fs::exists(dir / "a" / "b" / ("plot.svg.tmp" + dead)));
    EXPECT_EQ(manta::core::remove_stale_temporaries(dir, true), 1u);
    EXPECT_FALSE(fs::exists(dir / "a" / "b" / ("plot.svg.tmp" + dead)));
    EXPECT_EQ(manta::core::remove_stale_temporaries(dir / "missing", true), 0u);
    fs::remove_all(dir);
}

TEST(Files, OutputFolderCheckedBeforeWork) {
    const fs::path dir = scratch("prepare");
    std::ofstream(dir / "plain") << "x";
    // Under a file: the option, the path and the system's reason, in one line.
    std::string msg =
        io_error([&] { manta::core::prepare_output_folder(dir / "plain" / "run", "--out"); });
    expect_parts(msg, {"--out", (dir / "plain" / "run").string(), "cannot create the folder",
                       "Not a directory"});
    msg = io_error([&] { manta::core::prepare_output_folder(dir / "plain", "--out"); });
    expect_parts(msg, {"--out", (dir / "plain").string(), "is not a folder"});
    msg = io_error([&] { manta::core::prepare_output_folder("", "--out"); });
    expect_parts(msg, {"--out is empty"});
    msg = io_error([&] { manta::core::prepare_output_file(dir, "--html"); });
    expect_parts(msg, {"--html", "is a folder"});
    msg = io_error(
        [&] { manta::core::prepare_output_file(dir / "plain" / "x" / "r.html", "--html"); });
    expect_parts(msg, {"--html", (dir / "plain" / "x").string(), "Not a directory"});
    // A good path: created, nothing left in it.
    manta::core::prepare_output_folder(dir / "new" / "run", "--out");
    EXPECT_TRUE(fs::is_directory(dir / "new" / "run"));
    EXPECT_TRUE(fs::is_empty(dir / "new" / "run"));
    manta::core::prepare_output_file(dir / "f" / "t.csv", "--out");
    EXPECT_TRUE(fs::is_directory(dir / "f"));
    EXPECT_FALSE(fs::exists(dir / "f" / "t.csv"));
    fs::remove_all(dir);
}

TEST(RunFolderLock, SecondHolderIsToldWhoHoldsIt) {
    const fs::path dir = scratch("lock");
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t holder = ::fork();
    ASSERT_GE(holder, 0);
    if (holder == 0) {
        ::close(ready[0]);
        const manta::core::RunFolderLock lock(dir, "tables");
        (void)!::write(ready[1], "x", 1);
        for (;;) ::pause();
    }
    ::close(ready[1]);
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    ::close(ready[0]);
    const std::string msg = io_error([&] { const manta::core::RunFolderLock l(dir, "cfd"); });
    expect_parts(msg, {dir.string() + " is in use by manta tables (pid " + std::to_string(holder) +
                           ") since 20",
                       "--out"});
    // The holder is killed: the kernel releases its lock and the next command takes it.
    ::kill(holder, SIGKILL);
    int status = 0;
    ::waitpid(holder, &status, 0);
    {
        const manta::core::RunFolderLock lock(dir, "cfd");
        const std::string record = manta::core::read_file(dir / ".manta.lock");
        EXPECT_NE(record.find("pid " + std::to_string(::getpid()) + "\n"), std::string::npos)
            << record;
        EXPECT_NE(record.find("command cfd\n"), std::string::npos) << record;
        // Within one process too, a second lock on the folder is refused.
        EXPECT_THROW(manta::core::RunFolderLock(dir, "report", "--figures"), manta::IoError);
    }
    // Released when the holder goes out of scope.
    EXPECT_NO_THROW(manta::core::RunFolderLock(dir, "tables"));
    fs::remove_all(dir);
}

TEST(RunFolderLock, UnwritableFolderNamed) {
    const fs::path dir = scratch("lock_bad");
    std::ofstream(dir / "plain") << "x";
    const std::string msg =
        io_error([&] { const manta::core::RunFolderLock l(dir / "plain" / "run", "tables"); });
    expect_parts(msg, {"--out", (dir / "plain" / "run").string(), "Not a directory"});
    fs::remove_all(dir);
}

// ------------------------------------------------------------------------------------ messages

TEST(Printable, EscapesControlBytesAndKeepsUtf8) {
    using manta::core::printable;
    EXPECT_EQ(printable("plain text, 1.5 \\ back"), "plain text, 1.5 \\ back");
    EXPECT_EQ(printable("a\x1b[31mb\rc\nd\te"), "a\\x1b[31mb\\x0dc\\x0ad\\x09e");
    EXPECT_EQ(printable(std::string("x\0y", 3)), "x\\x00y");
    EXPECT_EQ(printable("del\x7f"), "del\\x7f");
    EXPECT_EQ(printable("\xc3\xa9t\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"),
              "\xc3\xa9t\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");  // été € and an emoji
    EXPECT_EQ(printable("\xc2\x9b"
                        "2J"),
              "\\xc2\\x9b2J");                                // C1 CSI
    EXPECT_EQ(printable("\xff\xc3"), "\\xff\\xc3");           // not UTF-8, cut off
    EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a surrogate
    EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");           // overlong '/'
    const std::string once = printable("\x1b]0;title\x07");
    EXPECT_EQ(printable(once), once);
}

TEST(Printable, EveryErrorMessageIsEscaped) {
    const manta::InputError e(std::string("value 'a\x1b[2J\0b' at line 3", 25));
    EXPECT_STREQ(e.what(), "value 'a\\x1b[2J\\x00b' at line 3");
    const std::string msg =
        input_error([] { (void)parse_csv("t,x\n0,\x1b[31mred\r1\n", "in.csv"); });
    EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
    expect_parts(msg, {"in.csv:2", "'\\x1b[31mred\\x0d1'"});
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
