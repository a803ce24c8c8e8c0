// The benchmarks' header block (bench_context.hpp): every field there and well formed, the commit
// the one git itself names for the tree (with "+dirty" exactly when a tracked file changed), and
// "unknown" said outright where there is no checkout. Git is the truth here, run by the test.
#include "tests/bench/support/bench_context.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "tests/bench/support/machine.hpp"

namespace fs = std::filesystem;
using gyrocal::bench::ContextField;
using gyrocal::bench::FormatContext;
using gyrocal::bench::ReadContext;
using gyrocal::bench::SourceCommit;

namespace {

// stdout of `command` (sh), trailing newline removed; fails the test when it exits non-zero.
std::string Sh(const std::string& command) {
    FILE* p = popen(command.c_str(), "r");
    EXPECT_NE(p, nullptr) << command;
    if (p == nullptr) return "";
    std::string out;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
    EXPECT_EQ(pclose(p), 0) << command;
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
}

std::map<std::string, std::string> AsMap(const std::vector<ContextField>& fields) {
    return {fields.begin(), fields.end()};
}

// A fresh git repository with one committed file, removed at the end of the test.
class ScratchRepo : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("bench_context_" + std::to_string(getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        std::ofstream(dir_ / "a.txt") << "one\n";
        git_ = "git -C '" + dir_.string() + "' ";
        Sh(git_ + "init -q && " + git_ + "add a.txt && " + git_ +
           "-c user.name=t -c user.email=t@example.com commit -q -m one");
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
    std::string git_;
};

}  // namespace

TEST(BenchContext, HasEveryFieldInOrderAndWellFormed) {
    char arg0[] = "build/bin/gyrocal_bench_x", arg1[] = "--seeds", arg2[] = "3 4";
    char* argv[] = {arg0, arg1, arg2};
    const std::time_t before = std::time(nullptr);
    const auto fields = ReadContext(3, argv);
    std::vector<std::string> keys;
    for (const auto& f : fields) keys.push_back(f.first);
    EXPECT_EQ(keys, (std::vector<std::string>{"date", "command", "commit", "host", "cpu", "memory",
                                              "kernel", "load"}));
    auto m = AsMap(fields);

    // The date: UTC, to the second, between the instants before and after the call (+-1 s for the
    // second boundary).
    std::smatch d;
    ASSERT_TRUE(std::regex_match(m["date"], d,
                                 std::regex(R"((\d{4})-(\d\d)-(\d\d) (\d\d):(\d\d):(\d\d) UTC)")))
        << m["date"];
    std::tm tm{};
    tm.tm_year = std::stoi(d[1]) - 1900;
    tm.tm_mon = std::stoi(d[2]) - 1;
    tm.tm_mday = std::stoi(d[3]);
    tm.tm_hour = std::stoi(d[4]);
    tm.tm_min = std::stoi(d[5]);
    tm.tm_sec = std::stoi(d[6]);
    const std::time_t printed = timegm(&tm);
    EXPECT_GE(printed, before - 1);
    EXPECT_LE(printed, std::time(nullptr) + 1);

    // The command as a shell would take it again: the argument with a space quoted.
    EXPECT_EQ(m["command"], "build/bin/gyrocal_bench_x --seeds '3 4'");

    char host[256] = {};
    gethostname(host, sizeof host - 1);
    EXPECT_EQ(m["host"], host);
    EXPECT_EQ(m["cpu"], gyrocal::bench::CpuModel() + ", " +
                            std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores online");
    EXPECT_TRUE(
        std::regex_match(m["memory"], std::regex(R"(\d+\.\d GiB total, \d+\.\d GiB available)")))
        << m["memory"];
    EXPECT_EQ(m["kernel"].rfind("Linux ", 0), 0u) << m["kernel"];
    EXPECT_NE(m["kernel"].find(Sh("uname -r")), std::string::npos) << m["kernel"];
    EXPECT_TRUE(std::regex_match(
        m["load"], std::regex(R"(\d+\.\d+ \d+\.\d+ \d+\.\d+ \(1, 5, 15 min averages, at start\))")))
        << m["load"];
}

TEST(BenchContext, CommitIsTheSourceTreesHeadAsGitNamesIt) {
    // The tree this test was built from is a checkout (the benchmarks are built from one); its
    // HEAD and whether a tracked file changed, by git itself.
    const std::string dir = GYROCAL_SOURCE_DIR;
    const std::string head = Sh("git -C '" + dir + "' rev-parse HEAD");
    const bool dirty = !Sh("git -C '" + dir + "' status --porcelain --untracked-files=no").empty();
    ASSERT_TRUE(std::regex_match(head, std::regex("[0-9a-f]{40}"))) << head;
    char arg0[] = "x";
    char* argv[] = {arg0};
    EXPECT_EQ(AsMap(ReadContext(1, argv))["commit"],
              head + (dirty ? "+dirty" : "") + " (" + dir + ")");
}

TEST_F(ScratchRepo, CleanTreeIsItsHeadAndATrackedChangeMakesItDirty) {
    const std::string head = Sh(git_ + "rev-parse HEAD");
    EXPECT_EQ(SourceCommit(dir_.string()), head);
    // An untracked file does not count (as for git describe --dirty).
    std::ofstream(dir_ / "untracked.txt") << "x\n";
    EXPECT_EQ(SourceCommit(dir_.string()), head);
    std::ofstream(dir_ / "a.txt") << "two\n";
    EXPECT_EQ(SourceCommit(dir_.string()), head + "+dirty");
}

TEST_F(ScratchRepo, AFolderInsideACheckoutIsNotACheckoutOfItsOwn) {
    // A tree copied into some other repository's folder: that repository's commit is not its own.
    fs::create_directories(dir_ / "copied_tree");
    const std::string inner = (dir_ / "copied_tree").string();
    EXPECT_EQ(SourceCommit(inner), "unknown (not a git checkout: " + inner + ")");
}

TEST(BenchContext, NoCheckoutSaysUnknown) {
    const fs::path dir =
        fs::temp_directory_path() / ("bench_context_nogit_" + std::to_string(getpid()));
    fs::create_directories(dir);
    // Only meaningful when the temporary folder is itself in no checkout.
    ASSERT_NE(std::system(("git -C '" + dir.string() + "' rev-parse 2>/dev/null").c_str()), 0);
    EXPECT_EQ(SourceCommit(dir.string()), "unknown (not a git checkout: " + dir.string() + ")");
    EXPECT_EQ(SourceCommit((dir / "missing").string()),
              "unknown (not a git checkout: " + (dir / "missing").string() + ")");
    fs::remove_all(dir);
}

TEST(BenchContext, FormatAlignsTheValuesOneFieldALine) {
    EXPECT_EQ(FormatContext({{"date", "D"}, {"command", "C x"}, {"load", "1 2 3"}}),
              "date:    D\ncommand: C x\nload:    1 2 3\n");
}

// machine.hpp's /proc reader, which the benchmarks use for their children and for themselves:
// touching 32 MiB raises this process' resident set by about that much (the allocator and page
// rounding may take a little less from it, hence 7/8), the peak is never below the current, and a
// process that does not exist reads as cpu_s -1.
TEST(ReadProcStats, SeesThisProcessGrowByWhatItTouches) {
    using gyrocal::bench::ReadProcStats;
    const gyrocal::bench::ProcStats before = ReadProcStats(getpid());
    ASSERT_GE(before.cpu_s, 0.0);
    ASSERT_GT(before.rss_kb, 0);
    constexpr size_t kBytes = 32u << 20;
    std::vector<char> touched(kBytes, 1);
    const gyrocal::bench::ProcStats after = ReadProcStats(getpid());
    EXPECT_GE(after.rss_kb - before.rss_kb, static_cast<int64_t>(kBytes / 1024 * 7 / 8));
    EXPECT_GE(after.hwm_kb, after.rss_kb);
    EXPECT_EQ(touched[kBytes - 1], 1);
    EXPECT_EQ(ReadProcStats(-1).cpu_s, -1.0);
}
