// The latency benchmark as a user runs it (a real process starting the real gyrocal-compensator,
// port 7931, TTL 0): bad options exit 2 naming the option; a short case exits 0, accounts for
// every sample and finds every checked rate equal to the library's. Its figures are not asserted
// (a benchmark's job, not a test's), only that they are ordered as percentiles must be.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <regex>
#include <string>

#include "lcmtypes/launch/child_process.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr const char* kUrl = "udpm://239.255.76.67:7931?ttl=0&recv_buf_size=4194304";

struct Ran {
    launch::ExitStatus status;
    std::string out, err;
};

Ran RunBench(const std::vector<std::string>& args, const std::string& name) {
    const std::string out = ::testing::TempDir() + name + ".out",
                      err = ::testing::TempDir() + name + ".err";
    std::vector<std::string> argv = {GYROCAL_BENCH_LATENCY_EXE};
    argv.insert(argv.end(), args.begin(), args.end());
    launch::ChildProcess p(argv, out, err);
    // Bounded but generous: a 1 s case plus the compensator's start on a loaded machine.
    const auto st = p.Wait(120s);
    EXPECT_TRUE(st.has_value()) << name << " did not end within 120 s";
    return {st.value_or(launch::ExitStatus{}), launch::ReadLog(out), launch::ReadLog(err)};
}

TEST(BenchCompensatorLatency, BadOptionsExitTwoNamingTheOption) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
        {{"--case", "4y100"}, "--case '4y100' is not valid"},
        {{"--case", "0x100"}, "--case '0x100' is not valid"},
        {{"--case", "4x20000"}, "--case '4x20000' is not valid"},
        {{"--case", "4x100x3"}, "--case '4x100x3' is not valid"},
        {{"--model", "cubic"}, "--model 'cubic' is not valid"},
        {{"--lcm-url", "udpm://239.255.76.67:7931?ttl=1"}, "give a udpm:// URL with ttl=0"},
        {{"--lcm-url", "memq://"}, "--lcm-url 'memq://' is not valid"},
        {{"--duration-s", "0"}, "--duration-s"},
        {{"--bogus"}, "--bogus"}};
    int n = 0;
    for (const auto& [args, says] : bad) {
        const Ran r = RunBench(args, "bad" + std::to_string(n++));
        EXPECT_TRUE(r.status.exited) << args[0];
        EXPECT_EQ(r.status.code, 2) << args[0] << ": " << r.err;
        EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("gyrocal_bench_compensator_latency:"), std::string::npos) << r.err;
    }
}

TEST(BenchCompensatorLatency, ShortCaseAccountsForEverySampleAndChecksEveryRate) {
    const Ran r = RunBench({"--case", "2x100", "--duration-s", "1", "--lcm-url", kUrl}, "short");
    ASSERT_TRUE(r.status.exited);
    ASSERT_EQ(r.status.code, 0) << r.out << r.err;
    std::smatch m;
    // 2 sensors x 100 Hz x 1 s = 200 samples, each received or counted lost
    ASSERT_TRUE(
        std::regex_search(r.out, m, std::regex(R"(sent (\d+)  received (\d+)  lost (\d+))")))
        << r.out;
    EXPECT_EQ(std::stoll(m[1]), 200);
    EXPECT_EQ(std::stoll(m[2]) + std::stoll(m[3]), 200);
    EXPECT_GT(std::stoll(m[2]), 0);
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(bit for bit: (\d+) of (\d+) checked)")))
        << r.out;
    EXPECT_EQ(m[1], m[2]);
    ASSERT_TRUE(std::regex_search(
        r.out, m,
        std::regex(R"(p50 ([\d.]+)  p90 ([\d.]+)  p99 ([\d.]+)  p99.9 ([\d.]+)  max ([\d.]+))")))
        << r.out;
    for (int i = 1; i < 5; ++i) EXPECT_LE(std::stod(m[i]), std::stod(m[i + 1])) << r.out;
    EXPECT_GT(std::stod(m[1]), 0.0);  // a rate cannot arrive before its sample was sent
    // The header block comes first (tests/bench/support/bench_context.hpp): date, commit, machine.
    EXPECT_EQ(r.out.rfind("date:", 0), 0u) << r.out;
    EXPECT_NE(r.out.find("\ncommit:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\ncpu:"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace gyrocal
