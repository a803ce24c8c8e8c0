// `gyrocal calibrate --source csv|log` with input that cannot be replayed: the cause is on the
// command's own output, not only in a child's log. A file that is bad in its header or first rows
// is refused before any process starts (exit 2, no run recorded); a bad row further down is found
// by gyrocal-csv-source during the run, which ends with the source's own error line printed under
// the abort line, stored as the run's reason, and shown by `gyrocal show` and `gyrocal report`.
// Port 7815, this file's own.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

constexpr int kPort = 7815;

// One unit at 100 Hz, `rows` rows; row `bad_row` (1-based, counted after the header) gets
// `bad_temp_v` in its temp_v column.
void WriteCsv(const std::string& path, int rows, int bad_row = -1,
              const std::string& bad_temp_v = "") {
    std::ofstream f(path);
    f << "time_s,sensor_id,gyro_v,temp_v\n";
    for (int i = 1; i <= rows; ++i) {
        f << (i - 1) * 0.01 << ",U1,2.5," << (i == bad_row ? bad_temp_v : "2.5") << "\n";
    }
}

struct Outcome {
    int code = -1;
    std::string printed;
};

Outcome Calibrate(const std::string& dir, const std::string& source, const std::string& input) {
    const std::string out = dir + "/calibrate.out";
    launch::ChildProcess cal({GYROCAL_CLI, "calibrate", "--source", source, "--input", input,
                              "--db", dir + "/run.db", "--lcm-url", UdpmUrl(kPort), "--log-dir",
                              dir + "/logs", "--quiet", "--wall-timeout-s", "120"},
                             out, out);
    const auto end = cal.Wait(150s);
    Outcome o;
    o.printed = launch::ReadLog(out);
    if (end && end->exited) o.code = end->code;
    return o;
}

// The first `n` lines of `text`: what the user sees on the first screen.
std::string FirstLines(const std::string& text, int n) {
    size_t pos = 0;
    for (int i = 0; i < n && pos != std::string::npos; ++i) {
        pos = text.find('\n', pos);
        if (pos != std::string::npos) ++pos;
    }
    return text.substr(0, pos == std::string::npos ? text.size() : pos);
}

// `input` refused before any process starts: exit 2, each of `says` printed (on the first screen,
// the first three lines, when `first_screen`), and no run recorded (no database).
Outcome ExpectRefusedUpFront(const std::string& dir, const std::string& source,
                             const std::string& input, const std::vector<std::string>& says,
                             bool first_screen = false) {
    const Outcome o = Calibrate(dir, source, input);
    EXPECT_EQ(o.code, 2) << o.printed;
    const std::string shown = first_screen ? FirstLines(o.printed, 3) : o.printed;
    for (const std::string& said : says)
        EXPECT_NE(shown.find(said), std::string::npos) << said << "\n" << o.printed;
    EXPECT_FALSE(std::filesystem::exists(dir + "/run.db")) << o.printed;
    return o;
}

TEST(CalibrateBadInput, EmptyCsvIsRefusedBeforeAnyProcessStarts) {
    const std::string dir = FreshDir("gyrocal_bad_empty");
    std::ofstream(dir + "/empty.csv").close();
    const Outcome o =
        ExpectRefusedUpFront(dir, "csv", dir + "/empty.csv",
                             {"gyrocal calibrate: error: " + dir +
                              "/empty.csv:1: column time_s: no header row: the file is empty"},
                             true);
    EXPECT_NE(o.printed.find("no run was started"), std::string::npos) << o.printed;
    // No process graph, so no database (above) and no logs folder.
    EXPECT_FALSE(std::filesystem::exists(dir + "/logs")) << o.printed;
}

TEST(CalibrateBadInput, HeaderWithoutTheRequiredColumnsIsRefusedBeforeAnyProcessStarts) {
    const std::string dir = FreshDir("gyrocal_bad_header");
    std::ofstream(dir + "/abc.csv") << "a,b,c\n1,2,3\n";
    // The line names the file, the line, the missing column and the columns that are required.
    ExpectRefusedUpFront(dir, "csv", dir + "/abc.csv",
                         {dir + "/abc.csv:1: column time_s", "time_s, sensor_id, gyro_v, temp_v"},
                         true);
}

TEST(CalibrateBadInput, HeaderOnlyCsvIsRefusedBeforeAnyProcessStarts) {
    const std::string dir = FreshDir("gyrocal_bad_norows");
    std::ofstream(dir + "/head.csv") << "time_s,sensor_id,gyro_v,temp_v\n";
    ExpectRefusedUpFront(
        dir, "csv", dir + "/head.csv",
        {dir + "/head.csv: no data rows: the header names the columns but no row follows"});
}

TEST(CalibrateBadInput, FileThatIsNotAnLcmLogIsRefusedBeforeAnyProcessStarts) {
    const std::string dir = FreshDir("gyrocal_bad_log");
    std::ofstream(dir + "/notalog.lcm") << "time_s,sensor_id\n";
    ExpectRefusedUpFront(dir, "log", dir + "/notalog.lcm",
                         {dir + "/notalog.lcm: not an LCM log: it starts with 0x74696D65; an LCM "
                                "log (written by lcm-logger) starts with the sync word "
                                "0xEDA1DA01"});
    std::ofstream(dir + "/empty.lcm").close();
    ExpectRefusedUpFront(dir, "log", dir + "/empty.lcm", {dir + "/empty.lcm: the file is empty"});
}

TEST(CalibrateBadInput, BadRowMidFileEndsTheRunWithTheSourcesOwnLinePrintedAndStored) {
    const std::string dir = FreshDir("gyrocal_bad_row");
    // Row 1001 is past the rows read ahead (input_check.hpp's kCheckRows = 100), so the run
    // starts and the source finds it.
    WriteCsv(dir + "/bad.csv", 1500, 1001, "abc");
    const Outcome o = Calibrate(dir, "csv", dir + "/bad.csv");
    EXPECT_EQ(o.code, 3) << o.printed;
    // The row is line 1002 of the file (the header is line 1).
    const std::string cause = dir + "/bad.csv:1002: column temp_v: 'abc'";
    // On the command's output: under the abort line and in the run's final line.
    EXPECT_NE(o.printed.find("aborting the run: csv source exit code 1; it said: " + cause),
              std::string::npos)
        << o.printed;
    EXPECT_NE(o.printed.find(": abort: csv source exit code 1; it said: " + cause),
              std::string::npos)
        << o.printed;

    // Stored as the run's reason ...
    Sql sql(dir + "/run.db");
    const auto run = sql.Rows("SELECT run_id, outcome, reason FROM runs WHERE run_id <> ''");
    ASSERT_EQ(run.size(), 1u);
    EXPECT_EQ(run[0][1], "abort");
    EXPECT_NE(run[0][2].find(cause), std::string::npos) << run[0][2];
    EXPECT_NE(run[0][2].find("is not a number"), std::string::npos) << run[0][2];

    // ... and shown by `gyrocal show` and on the report's first lines.
    launch::ChildProcess show({GYROCAL_CLI, "show", run[0][0], "--db", dir + "/run.db"},
                              dir + "/show.out", dir + "/show.out");
    ASSERT_TRUE(show.Wait(60s).has_value());
    EXPECT_NE(launch::ReadLog(dir + "/show.out").find(cause), std::string::npos)
        << launch::ReadLog(dir + "/show.out");
    launch::ChildProcess report(
        {GYROCAL_CLI, "report", run[0][0], "--db", dir + "/run.db", "--out", dir + "/report"},
        dir + "/report.out", dir + "/report.out");
    ASSERT_TRUE(report.Wait(120s).has_value());
    std::string html;
    for (const auto& f : std::filesystem::directory_iterator(dir + "/report"))
        if (f.path().extension() == ".html") html = launch::ReadLog(f.path().string());
    ASSERT_FALSE(html.empty()) << launch::ReadLog(dir + "/report.out");
    const size_t header_end = html.find("</header>");
    ASSERT_NE(header_end, std::string::npos);
    EXPECT_NE(html.substr(0, header_end).find("bad.csv:1002: column temp_v: &#39;abc&#39;"),
              std::string::npos)
        << html.substr(0, header_end);
}

}  // namespace
}  // namespace gyrocal
