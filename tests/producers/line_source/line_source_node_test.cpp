// gyrocal-line-source's node in one process over memq:// (LCM's in-process provider), reading a
// pipe the test has written and closed: each good line published as the samples it holds, bad
// lines skipped whole and counted, a stream without a header refused. Known truth: the values
// written in the lines. No sleep: Run() returns at the end of the input (--drain-s 0), and what
// it published last is handled after. The real process (stdin, a FIFO with wall time, exit
// codes): line_source_process_test.cpp.
#include "producers/line_source/line_source_node.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/text/number.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/producers/source_output.hpp"

namespace gyrocal {
namespace {

// A LineInput reading `text` from a pipe whose write end is closed (the text must fit the pipe's
// buffer, 64 KiB on Linux): the stream ends after it.
std::unique_ptr<line_source::LineInput> PipeOf(const std::string& text) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe() failed");
    const ssize_t n = write(fds[1], text.data(), text.size());
    close(fds[1]);
    if (n != static_cast<ssize_t>(text.size())) throw std::runtime_error("short write to pipe");
    return std::make_unique<line_source::LineInput>(fds[0], "test-pipe");
}

line_source::LineSourceOptions NodeOptions() {
    line_source::LineSourceOptions o = line_source::LineSourceOptions::Defaults();
    o.lcm_url = "memq://";
    o.drain_s = 0.0;
    return o;
}

// The messages the node published and has not yet dispatched to its own bus.
TEST(LineSourceNode, PublishesEachGoodLineAndSkipsBadOnesWhole) {
    // GIVEN a stream of two sensors, 10 rows each 10 ms apart, with the table turning by 1 deg
    // per row and the chamber at 30 degC; a NaN gyro_v after the 4th row and a garbage line
    // after the 12th
    const std::string header =
        "time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,encoder_deg,chamber_c";
    std::string text = header + "\n";
    struct Row {
        int64_t us;
        std::string id;
        double gyro_v;
    };
    std::vector<Row> rows;
    for (int i = 0; i < 10; ++i) {
        for (const char* id : {"S01", "S02"}) {
            const double gyro_v = 2.5 + 0.001 * i + (id[2] == '2' ? 0.1 : 0.0);
            rows.push_back({i * 10'000, id, gyro_v});
            text += std::to_string(i * 0.01) + "," + id + "," + text::Sig(gyro_v, 17) +
                    ",2.4,25,5," + std::to_string(i) + ",30\n";
            if (rows.size() == 4) text += "0.035,S01,nan,2.4,25,5,3,30\n";
            if (rows.size() == 12) text += "garbage\n";
        }
    }
    line_source::LineSourceNode node(NodeOptions(), PipeOf(text));
    testing::SourceOutput out(node.bus());
    const auto& [gyro, encoder, chamber, power] = out;
    // WHEN the node reads it to the end
    EXPECT_EQ(node.Run(), 0);
    testing::DrainBus(node.bus());
    // THEN every good row is a sample with its values, at start + time_s, in order, numbered
    // per sensor; the two bad lines are counted and nothing of them is published
    EXPECT_EQ(node.rows_published(), 20);
    EXPECT_EQ(node.bad_lines(), 2);
    // (gyro_v written with 17 significant digits: exact)
    testing::ExpectSamplesOfRows(gyro, rows, [](const gyro_sample_t& g, size_t) {
        EXPECT_EQ(g.temp_v, 2.4);
        EXPECT_EQ(g.temp_c, 25.0);
        EXPECT_EQ(g.supply_v, 5.0);
    });
    // One encoder reading per time step (the second sensor's row at the same time adds none),
    // the chamber once: its period is 1 s of data time and the stream holds 0.09 s.
    ASSERT_EQ(encoder.size(), 10u);
    for (size_t i = 0; i < encoder.size(); ++i) {
        EXPECT_EQ(encoder[i].angle_deg, static_cast<double>(i));
        EXPECT_EQ(encoder[i].utime, csv::kDefaultStartUtime + static_cast<int64_t>(i) * 10'000);
    }
    ASSERT_EQ(chamber.size(), 1u);
    EXPECT_EQ(chamber[0].air_c, 30.0);
}

TEST(LineSourceNode, AStreamWithoutAHeaderFails) {
    line_source::LineSourceNode node(NodeOptions(), PipeOf("0,S01,2.5,2.5\n"));
    std::vector<gyro_sample_t> gyro;
    testing::CollectInto(node.bus(), channels::AllSensors(channels::kGyroPrefix), gyro);
    EXPECT_EQ(node.Run(), 1);
    testing::DrainBus(node.bus());
    EXPECT_EQ(node.rows_published(), 0);
    EXPECT_TRUE(gyro.empty());
}

}  // namespace
}  // namespace gyrocal
