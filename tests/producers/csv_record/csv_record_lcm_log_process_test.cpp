// LCM logs as a source: a run published by gyrocal-csv-source is recorded with lcm-logger, then
// replayed with lcm-logplayer into gyrocal-csv-record; the replay holds the same samples as the
// original CSV (utime travels inside the messages, so replay timing does not change the data).
//
// Debian's lcm-logger 1.3.1 lists "-l" in its help but rejects it: the URL must be given as
// --lcm-url=URL. lcm-logplayer accepts -l URL (and --lcm-url=URL).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/producers/producer_process_support.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;

// This test's own channel, only to see when lcm-logger has started recording.
constexpr const char* kProbeChannel = "GYROCAL_TEST_LOG_PROBE";

// Events in an LCM log whose channel starts with `prefix`.
int CountEvents(const std::string& path, const std::string& prefix) {
    lcm::LogFile file(path, "r");
    if (!file.good()) return -1;
    int n = 0;
    while (const lcm::LogEvent* e = file.readNextEvent()) {
        if (e->channel.rfind(prefix, 0) == 0) ++n;
    }
    return n;
}

TEST(LcmLog, LoggedRunReplaysToTheSameSamples) {
    if (std::string(GYROCAL_LCM_LOGGER).empty() || std::string(GYROCAL_LCM_LOGPLAYER).empty()) {
        GTEST_SKIP() << "lcm-logger/lcm-logplayer not installed (Debian package liblcm-bin)";
    }
    Scratch dir("lcm_log");
    const std::string url = UdpmUrl(7736);
    const std::string log = dir.Path("run.lcmlog");
    // 3 sensors at 50 Hz for 2 s, replayed in real time: 150 msg/s. lcm-logger 1.3.1 queues only
    // 30 messages per subscription (it drops beyond), so this gives it 200 ms of slack when a
    // loaded machine deschedules it; faster runs lost samples in the logger under ctest -j2.
    WriteSyntheticCsv(dir.Path("in.csv"), SyntheticSpec{{"S01", "S02", "S03"}, 50.0, 2.0, 3});

    // GIVEN lcm-logger recording the test's multicast group
    launch::ChildProcess logger(
        {GYROCAL_LCM_LOGGER, "--lcm-url=" + url, "-f", "-q", "--flush-interval=20", log}, "",
        dir.Path("logger.err"));
    {
        // It is ready once a probe shows up in its file (bounded; the probe channel is this
        // test's own and nothing subscribes to it).
        bus::Bus probe(bus::BusOptions{url});
        const uint8_t byte = 0;
        testing::WaitUntil(
            [&] {
                if (std::filesystem::exists(log) && std::filesystem::file_size(log) > 0)
                    return true;
                probe.PublishRaw(kProbeChannel, &byte, 1);
                return false;
            },
            10s, 50ms);
        ASSERT_GT(std::filesystem::file_size(log), 0u) << Slurp(dir.Path("logger.err"));
    }
    // WHEN a CSV run is published and logged
    launch::ChildProcess source = StartCsvSource(dir, url, "in.csv", {"--speed", "1"});
    EXPECT_EQ(WaitExit(source, 20s).code, 0) << Slurp(dir.Path("source.err"));
    logger.Signal(SIGINT);
    const launch::ExitStatus l = WaitExit(logger, 10s);
    EXPECT_TRUE(l.exited && l.code == 0) << l.Describe() << Slurp(dir.Path("logger.err"));
    // The log itself must hold every sample (tells a logger loss from a replay loss).
    EXPECT_EQ(CountEvents(log, std::string(channels::kGyroPrefix)), 300);

    // AND the log is replayed through lcm-logplayer into the CSV recorder
    launch::ChildProcess rec = StartCsvRecord(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess player({GYROCAL_LCM_LOGPLAYER, "-l", url, "-s", "2", log},
                                dir.Path("player.out"), dir.Path("player.err"));
    const launch::ExitStatus p = WaitExit(player, 20s);
    EXPECT_TRUE(p.exited && p.code == 0) << p.Describe() << Slurp(dir.Path("player.err"));
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);

    // THEN the replay holds exactly the samples of the original file
    ExpectSameSamples(ReadCsvFile(dir.Path("in.csv")), ReadCsvFile(dir.Path("out.csv")));
}

}  // namespace
}  // namespace gyrocal::test
