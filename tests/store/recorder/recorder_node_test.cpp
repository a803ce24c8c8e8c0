// The recorder's node in one process over memq:// (LCM's in-process provider): messages published
// into the node's own bus become rows of a real SQLite file; a seq gap and a message of a known
// type that does not decode are counted as losses of the run in force; an unknown type is kept
// whole in raw_events; a bad channel regex is refused before anything subscribes. The real
// process over UDP multicast is recorder_process_test.cpp.
#include "store/recorder/node/recorder_node.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/store/recorder/recorder_harness.hpp"

namespace gyrocal::testing {
namespace {

recorder::node::RecorderOptions MemqOptions(const std::string& db) {
    auto o = recorder::node::RecorderOptions::Defaults();
    o.db_path = db;
    o.lcm_url = "memq://";
    o.batch_ms = 20;
    return o;
}

TEST(RecorderNode, RecordsTheRunAndCountsWhatWasLost) {
    // GIVEN a recorder node on memq:// writing a fresh database
    const std::string db = FreshDbPath("recorder_node_rows");
    {
        recorder::node::RecorderNode node(MemqOptions(db),
                                          recorder::node::OpenRecorderDatabase(db));
        bus::Bus& bus = node.bus();
        // WHEN a run starts, S01 sends seq 0..9 except 4 and 5 (2 lost), S02 sends 0..4, a
        // foreign type arrives, a gyro sample is cut short (known fingerprint, no decode), and
        // the run stops
        bus.Publish(std::string(channels::kRunEvent), RunEvent("R1", "start", {"S01", "S02"}));
        for (int64_t seq = 0; seq < 10; ++seq) {
            if (seq != 4 && seq != 5) bus.Publish(channels::Gyro("S01"), Gyro("S01", seq));
        }
        for (int64_t seq = 0; seq < 5; ++seq) bus.Publish(channels::Gyro("S02"), Gyro("S02", seq));
        const std::vector<uint8_t> foreign = {0x01, 0x23, 0x45, 0x67, 0x89, 0xab, 0xcd, 0xef, 1, 2};
        bus.PublishRaw("SOMEONE_ELSES_TYPE", foreign.data(), static_cast<int>(foreign.size()));
        gyro_sample_t whole = Gyro("S02", 5);
        std::vector<uint8_t> cut(static_cast<size_t>(whole.getEncodedSize()));
        whole.encode(cut.data(), 0, static_cast<int>(cut.size()));
        bus.PublishRaw(channels::Gyro("S02"), cut.data(), 12);
        bus.Publish(std::string(channels::kRunEvent), RunEvent("R1", "stop", {"S01", "S02"}));
        // and the node stops (what LCM already queued is recorded, then committed)
        EXPECT_EQ(node.Finish(), 0);
    }
    // THEN every row is in its table under the run, and the losses name what was missed
    EXPECT_EQ(
        Count(db, "SELECT count(*) FROM gyro_samples WHERE run_id = 'R1' AND sensor_id = 'S01'"),
        8);
    EXPECT_EQ(
        Count(db, "SELECT count(*) FROM gyro_samples WHERE run_id = 'R1' AND sensor_id = 'S02'"),
        5);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM run_events WHERE run_id = 'R1'"), 2);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM runs WHERE run_id = 'R1' AND outcome = 'stop'"), 1);
    EXPECT_EQ(Count(db,
                    "SELECT coalesce(sum(seq_gaps), 0) FROM losses WHERE run_id = 'R1' AND "
                    "channel = 'GYRO_S01'"),
              2);
    EXPECT_EQ(Count(db,
                    "SELECT coalesce(sum(decode_errors), 0) FROM losses WHERE run_id = 'R1' "
                    "AND channel = 'GYRO_S02'"),
              1);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM raw_events WHERE channel = 'SOMEONE_ELSES_TYPE' AND "
                    "reason = 'unknown_type' AND fingerprint = '0123456789abcdef' AND "
                    "length(data) = 10"),
              1);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM raw_events WHERE channel = 'GYRO_S02'"), 1);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM recorder_sessions WHERE stopped_wall_utime IS NOT "
                    "NULL"),
              1);
}

TEST(RecorderNode, ChannelRegexIsRecordedOnly) {
    // GIVEN a node that records GYRO_S01 only
    const std::string db = FreshDbPath("recorder_node_channels");
    {
        auto o = MemqOptions(db);
        o.channels = "GYRO_S01|RUN_EVENT";
        recorder::node::RecorderNode node(o, recorder::node::OpenRecorderDatabase(db));
        node.bus().Publish(std::string(channels::kRunEvent), RunEvent("R2", "start", {"S01"}));
        for (int64_t seq = 0; seq < 3; ++seq) {
            node.bus().Publish(channels::Gyro("S01"), Gyro("S01", seq));
            node.bus().Publish(channels::Gyro("S02"), Gyro("S02", seq));
        }
        EXPECT_EQ(node.Finish(), 0);
    }
    // THEN the other sensor's samples are not in the database at all
    EXPECT_EQ(Count(db, "SELECT count(*) FROM gyro_samples WHERE sensor_id = 'S01'"), 3);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM gyro_samples WHERE sensor_id = 'S02'"), 0);
}

TEST(RecorderNode, BadChannelRegexIsExplained) {
    EXPECT_EQ(recorder::node::ValidateLcmChannelRegex(".*"), "");
    EXPECT_EQ(recorder::node::ValidateLcmChannelRegex("GYRO_.*|RUN_EVENT"), "");
    const std::string why = recorder::node::ValidateLcmChannelRegex("(");
    EXPECT_NE(why.find("'(' is not a valid channel regex"), std::string::npos) << why;
    EXPECT_NE(why.find("e.g. '.*'"), std::string::npos) << why;
}

TEST(RecorderNode, DatabaseThatIsNotGyrocalIsRefused) {
    const std::string path = FreshDbPath("recorder_node_notdb");
    {
        std::FILE* f = std::fopen(path.c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs("this is not an SQLite file, it is long enough to have a header page\n", f);
        std::fclose(f);
    }
    EXPECT_ANY_THROW(recorder::node::OpenRecorderDatabase(path));
}

}  // namespace
}  // namespace gyrocal::testing
