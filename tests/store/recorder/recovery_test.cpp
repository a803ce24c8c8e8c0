// What a restarted recorder, fitter or compensator gets back from the database, without sockets:
// the open run of the recorder's own bus (two chambers in one file never continue each other's
// runs), plateaus and sensitivity points kept once however often they are heard, and the
// recovery messages that rebuild a restarted fitter or compensator.
#include "store/recorder/recovery.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "store/db/query.hpp"
#include "store/db/writer.hpp"
#include "store/recorder/open_run.hpp"
#include "tests/store/row_builders.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::recorder {
namespace {

using namespace gyrocal::db;

using testing::FreshDbPath;

RunEventRow Event(const std::string& run, const std::string& event, const std::string& config,
                  int64_t recv) {
    RunEventRow e = testing::RunEvent(run, event, {"A1"}, recv);
    e.config_json = config;
    return e;
}

// A one-minute plateau starting at `id` [us].
PlateauRow Plateau(const std::string& run, const std::string& sensor, int64_t id, double mean_v) {
    PlateauRow p = testing::Plateau(run, sensor, id, id + 60'000'000);
    p.setpoint_c = 25;
    p.gyro_mean_v = mean_v;
    p.temp_mean_c = 25.1;
    return p;
}

// A five-second rotation starting at `id` [us], clockwise.
SensitivityRow Point(const std::string& run, const std::string& sensor, int64_t id, bool accepted) {
    SensitivityRow s = testing::Rotation(run, sensor, id, id + 5'000'000);
    s.direction = -1;
    s.sensitivity_v_per_dps = 0.006;
    s.accepted = accepted;
    s.reject_reason = accepted ? "" : "12 samples missing (sequence gaps)";
    return s;
}

TEST(OpenRunOnBus, ARecorderContinuesOnlyARunOfItsOwnBus) {
    const std::string path = FreshDbPath("open_run.db");
    {
        StoreWriter w(path, {"rec", "h", 1});
        // GIVEN chamber 1's run (port 7667), then chamber 2's (port 7668), both open, and a
        // closed newer run of chamber 1
        w.Write({Event("C1", "start", R"({"lcm_url":"udpm://239.255.76.67:7667?ttl=1"})", 10),
                 Event("C2", "start", R"({"lcm_url":"udpm://239.255.76.67:7668?ttl=0"})", 20),
                 Event("C1old", "start", R"({"lcm_url":"udpm://239.255.76.67:7667"})", 5),
                 Event("C1old", "stop", "", 6)},
                {});
    }
    Db db(path, Db::Mode::kReadOnly);
    // THEN each bus finds its own open run, whatever the TTL or buffer options say
    EXPECT_EQ(OpenRunOnBus(db, "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"), "C1");
    EXPECT_EQ(OpenRunOnBus(db, "udpm://239.255.76.67:7668?ttl=1"), "C2");
    EXPECT_EQ(OpenRunOnBus(db, "udpm://239.255.76.67:7669"), "") << "no run of a third chamber";
}

TEST(OpenRunOnBus, ARunThatNamesNoBusIsAnyBus) {
    const std::string path = FreshDbPath("open_run_nobus.db");
    {
        StoreWriter w(path, {"rec", "h", 1});
        w.Write({Event("HAND", "start", R"({"sequencer":{}})", 10)}, {});
    }
    Db db(path, Db::Mode::kReadOnly);
    EXPECT_EQ(OpenRunOnBus(db, "udpm://239.255.76.67:7668"), "HAND");
    EXPECT_EQ(OpenRunOnBus(db, "memq://"), "HAND");
}

TEST(Recovery, StoredPointsComeBackOnceAsTheMessagesTheyWere) {
    const std::string path = FreshDbPath("recovery.db");
    {
        StoreWriter w(path, {"rec", "h", 1});
        w.Write({Event("R", "start", "{}", 1), Plateau("R", "A1", 200, 2.51),
                 Plateau("R", "A1", 100, 2.50), Point("R", "A1", 300, true),
                 Point("R", "A1", 400, false)},
                {});
        // WHEN the same plateau and point are heard again (a recovery's republication)
        w.Write({Plateau("R", "A1", 100, 2.50), Point("R", "A1", 300, true)}, {});
        CoeffSetRow c;
        c.run_id = "R";
        c.sensor_id = "A1";
        c.source = "fitter";
        c.coeff_set_id = 77;
        c.utime = 77;
        c.offset.quantity = "offset_v";
        c.offset.term_names = {"1", "dT"};
        c.offset.coeffs = {2.5, 1e-4};
        c.offset.covariance = {{1e-8, 0}, {0, 1e-9}};
        c.sensitivity.quantity = "sensitivity_v_per_dps";
        c.sensitivity.term_names = {"1"};
        c.sensitivity.coeffs = {0.006};
        c.sensitivity.covariance = {{1e-12}};
        c.plateau_ids = {100, 200};
        c.rotation_ids = {300};
        c.recv_utime = 500;
        w.Write({c}, {});
    }
    auto db = OpenForQuery(path);
    // THEN each is stored once
    EXPECT_EQ(ShowRun(*db, "R").plateaus.size(), 2u);
    EXPECT_EQ(ShowRun(*db, "R").sensitivity_points.size(), 2u);
    // AND the recovery gives them back in acquisition order, with their fields, rejected too
    const RecoveredRun r = ReadRecovery(*db, "R");
    ASSERT_EQ(r.plateaus.size(), 2u);
    EXPECT_EQ(r.plateaus[0].plateau_id, 100);
    EXPECT_EQ(r.plateaus[0].run_id, "R");
    EXPECT_DOUBLE_EQ(r.plateaus[1].gyro_mean_v, 2.51);
    EXPECT_TRUE(std::isnan(r.plateaus[0].supply_mean_v));
    ASSERT_EQ(r.rotations.size(), 2u);
    EXPECT_TRUE(r.rotations[0].accepted);
    EXPECT_FALSE(r.rotations[1].accepted);
    EXPECT_EQ(r.rotations[1].reject_reason, "12 samples missing (sequence gaps)");
    EXPECT_EQ(r.rotations[0].direction, -1);
    ASSERT_EQ(r.newest_coeffs.size(), 1u);
    const coeff_set_t& c = r.newest_coeffs[0];
    EXPECT_EQ(c.coeff_set_id, 77);
    EXPECT_EQ(c.offset.num_terms, 2);
    EXPECT_EQ(c.offset.term_names, (std::vector<std::string>{"1", "dT"}));
    EXPECT_DOUBLE_EQ(c.offset.covariance[1][1], 1e-9);
    EXPECT_EQ(c.num_plateaus, 2);
    EXPECT_EQ(c.rotation_ids, (std::vector<int64_t>{300}));
    // A message built from it encodes (array lengths agree with their counts).
    std::vector<uint8_t> buf(static_cast<size_t>(c.getEncodedSize()));
    EXPECT_GT(c.encode(buf.data(), 0, static_cast<int>(buf.size())), 0);
    EXPECT_THROW(ReadRecovery(*db, "nope"), NotFound);
}

}  // namespace
}  // namespace gyrocal::recorder
