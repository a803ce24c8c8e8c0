// gyrocal-log-source's node in one process over memq:// (LCM's in-process provider): a log written
// as lcm-logger writes it (log_writer.hpp), published on the node's own bus at speed 1000. Known
// truth: the events written; each one on a published channel comes back once, in order, its bytes
// unchanged; the recorded run's flow control and the channels outside --channels do not. No
// sleep: Run() returns after the last event (--drain-s 0) and what it published last is handled
// after. The real process (flow control with gyrocal-csv-record, a damaged log):
// log_source_process_test.cpp.
#include "producers/log_source/log_source_node.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/producers/log_source/log_writer.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using Event = std::pair<std::string, std::vector<uint8_t>>;  // channel, bytes

TEST(LogSourceNode, PublishesEachSelectedEventOnceWithItsBytesUnchanged) {
    // GIVEN a log of 30 events 1 ms apart on GYRO_S01, ENCODER, FLOW_MARK (the recorded run's
    // flow control) and NOISE_S01 (outside --channels)
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("gyrocal_log_source_node_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "run.lcmlog").string();
    const std::vector<std::string> written_on = {"GYRO_S01", "ENCODER", "FLOW_MARK", "NOISE_S01"};
    std::vector<Event> expected;
    {
        std::ofstream out(file, std::ios::binary);
        for (int64_t n = 0; n < 30; ++n) {
            const std::string& channel = written_on[static_cast<size_t>(n) % written_on.size()];
            std::vector<uint8_t> data(1 + static_cast<size_t>(n));
            for (size_t k = 0; k < data.size(); ++k) data[k] = static_cast<uint8_t>(n * 7 + k);
            test::WriteEvent(out, n, 1'000'000 + n * 1000, channel, data);
            if (channel == "GYRO_S01" || channel == "ENCODER") expected.emplace_back(channel, data);
        }
    }
    log_source::LogSourceOptions o = log_source::LogSourceOptions::Defaults();
    o.file = file;
    o.lcm_url = "memq://";
    o.speed = 1000;  // 29 ms of recorded time in 29 us
    o.drain_s = 0;
    o.channels = "GYRO_.*|ENCODER|FLOW_.*";
    ASSERT_EQ(o.Validate(), "");
    const int64_t events = log_source::CheckLog(file);
    ASSERT_EQ(events, 30);
    log_source::LogSourceNode node(o, events);
    std::vector<Event> heard;
    node.bus().SubscribeRaw(".*", [&](const lcm::ReceiveBuffer& rb, const std::string& channel) {
        if (channel == channels::kStatus) return;  // the node's own heartbeat
        const auto* p = static_cast<const uint8_t*>(rb.data);
        heard.emplace_back(channel, std::vector<uint8_t>(p, p + rb.data_size));
    });
    // WHEN the node publishes it
    EXPECT_EQ(node.Run(), 0);
    ASSERT_TRUE(testing::HandleUntil(
        node.bus(), [&] { return !node.bus().Handle(0ms); }, 10'000ms, 0ms));
    // THEN the GYRO_S01 and ENCODER events, in order, bytes unchanged; no FLOW_MARK (not
    // replayed even when --channels names it), no NOISE_S01
    EXPECT_EQ(node.published(), static_cast<int64_t>(expected.size()));
    ASSERT_EQ(heard.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(heard[i].first, expected[i].first) << i;
        EXPECT_EQ(heard[i].second, expected[i].second) << i;
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
