// The built-in profile: setpoints in order, a dwell at each, +move and -move, then done.
#include <gtest/gtest.h>

#include "sim/builtin_profile.hpp"
#include "sim/rig.hpp"
#include "sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

class ProfileSink : public testing::RecordingSink {
public:
    ProfileSink(BuiltinProfile& p, Rig& r) : profile(p), rig(r) {}
    void OnChamber(const ChamberReading& c) override {
        profile.OnChamber(c, rig);
        RecordingSink::OnChamber(c);
    }
    BuiltinProfile& profile;
    Rig& rig;
};

TEST(SimBuiltinProfile, RunsSetpointsDwellsAndRotates) {
    RigConfig c = testing::QuietConfig();
    c.thermal.ramp_c_per_min = 30.0;
    ProfileConfig pc;
    pc.setpoints_c = {-10.0, 40.0};
    pc.dwell_s = 60.0;
    pc.rest_s = 10.0;
    BuiltinProfile profile(pc);
    Rig rig(c);
    ProfileSink sink(profile, rig);
    int64_t t = c.start_utime;
    while (!profile.done() && t < c.start_utime + 4'000'000'000LL) {
        t += 10'000'000;
        rig.RunUntil(t, sink);
    }
    ASSERT_TRUE(profile.done());
    // Chamber orders 1 then 2, each reached before the table moved.
    std::vector<int64_t> ids;
    for (const auto& ch : sink.data.chamber) {
        if (ids.empty() || ids.back() != ch.cmd_id) ids.push_back(ch.cmd_id);
    }
    EXPECT_EQ(ids, (std::vector<int64_t>{-1, 1, 2}));
    // Two +90/-90 pairs: the table went to 90 twice and ended where it started.
    int moves_up = 0;
    for (size_t i = 1; i < sink.data.encoder.size(); ++i) {
        const auto &a = sink.data.encoder[i - 1], &b = sink.data.encoder[i];
        if (a.true_angle_deg < 90.0 && b.true_angle_deg >= 90.0) ++moves_up;
    }
    EXPECT_EQ(moves_up, 2);
    EXPECT_DOUBLE_EQ(sink.data.encoder.back().true_angle_deg, 0.0);
    // The first move began only after the dwell at -10 degC: air at setpoint by then.
    for (size_t i = 0; i < sink.data.encoder.size(); ++i) {
        if (sink.data.encoder[i].true_angle_deg != 0.0) {
            const double t_s = (sink.data.encoder[i].utime - c.start_utime) * 1e-6;
            const auto& ch = sink.data.chamber[static_cast<size_t>(t_s)];
            EXPECT_EQ(ch.cmd_id, 1);
            EXPECT_TRUE(ch.at_setpoint);
            EXPECT_GT(t_s, 70.0 + 60.0);  // 35 K at 30 K/min = 70 s, then the 60 s dwell
            break;
        }
    }
}

}  // namespace
}  // namespace gyrocal::sim

namespace gyrocal::sim {
namespace {

// Stops the rig at the report where the profile finished, as the process does.
class StoppingSink : public ProfileSink {
public:
    using ProfileSink::ProfileSink;
    void OnChamber(const ChamberReading& c) override {
        ProfileSink::OnChamber(c);
        if (profile.done()) rig.StopAfterCurrentEvent();
    }
};

testing::Recorded RunProfile(int64_t chunk_us) {
    RigConfig c = RigConfig::Defaults();
    c.num_units = 2;
    c.thermal.ramp_c_per_min = 60.0;
    ProfileConfig pc;
    pc.setpoints_c = {35.0};
    pc.dwell_s = 20.0;
    pc.rest_s = 5.0;
    BuiltinProfile profile(pc);
    Rig rig(c);
    StoppingSink sink(profile, rig);
    int64_t t = c.start_utime;
    while (!profile.done() && t < c.start_utime + 3'600'000'000LL) {
        t += chunk_us;
        rig.RunUntil(t, sink);
    }
    return sink.data;
}

TEST(SimBuiltinProfile, EndsAtTheSameSampleWhateverTheBatching) {
    const testing::Recorded a = RunProfile(1'000'000);
    const testing::Recorded b = RunProfile(7'777);
    ASSERT_FALSE(a.chamber.empty());
    ASSERT_EQ(a.gyro.size(), b.gyro.size());
    EXPECT_EQ(a.gyro.back().utime, b.gyro.back().utime);
    EXPECT_EQ(a.gyro.back().gyro_v, b.gyro.back().gyro_v);
    // It ended at a CHAMBER_STATE instant: the last report and the last samples share a time.
    EXPECT_EQ(a.chamber.back().utime, a.gyro.back().utime);
}

}  // namespace
}  // namespace gyrocal::sim
