// The built-in profile: setpoints in order, a dwell at each, +move and -move, then done.
#include "producers/sim/builtin_profile.hpp"

#include <gtest/gtest.h>

#include "producers/sim/rig.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

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

// Stops the rig at the report where the profile finished, as the process does.
class StoppingSink : public ProfileSink {
public:
    using ProfileSink::ProfileSink;
    void OnChamber(const ChamberReading& c) override {
        ProfileSink::OnChamber(c);
        if (profile.done()) rig.StopAfterCurrentEvent();
    }
};

struct ProfileRun {
    bool done;
    testing::Recorded data;
};

// `c`'s rig under the built-in profile `pc`, run in steps of `chunk_us` until the profile is done
// or `limit_us` have passed; `Sink` (a ProfileSink) sees every reading.
template <class Sink>
ProfileRun RunProfile(const RigConfig& c, ProfileConfig pc, int64_t chunk_us, int64_t limit_us) {
    BuiltinProfile profile(std::move(pc));
    Rig rig(c);
    Sink sink(profile, rig);
    for (int64_t t = c.start_utime; !profile.done() && t < c.start_utime + limit_us;) {
        t += chunk_us;
        rig.RunUntil(t, sink);
    }
    return {profile.done(), sink.data};
}

TEST(SimBuiltinProfile, RunsSetpointsDwellsAndRotates) {
    RigConfig c = testing::QuietConfig();
    c.thermal.ramp_c_per_min = 30.0;
    const ProfileRun run =
        RunProfile<ProfileSink>(c, {.setpoints_c = {-10.0, 40.0}, .dwell_s = 60.0, .rest_s = 10.0},
                                10'000'000, 4'000'000'000LL);
    ASSERT_TRUE(run.done);
    const testing::Recorded& data = run.data;
    // Chamber orders 1 then 2, each reached before the table moved.
    std::vector<int64_t> ids;
    for (const auto& ch : data.chamber) {
        if (ids.empty() || ids.back() != ch.cmd_id) ids.push_back(ch.cmd_id);
    }
    EXPECT_EQ(ids, (std::vector<int64_t>{-1, 1, 2}));
    // Two +90/-90 pairs: the table went to 90 twice and ended where it started.
    int moves_up = 0;
    for (size_t i = 1; i < data.encoder.size(); ++i) {
        const auto &a = data.encoder[i - 1], &b = data.encoder[i];
        if (a.true_angle_deg < 90.0 && b.true_angle_deg >= 90.0) ++moves_up;
    }
    EXPECT_EQ(moves_up, 2);
    EXPECT_DOUBLE_EQ(data.encoder.back().true_angle_deg, 0.0);
    // The first move began only after the dwell at -10 degC: air at setpoint by then.
    for (size_t i = 0; i < data.encoder.size(); ++i) {
        if (data.encoder[i].true_angle_deg != 0.0) {
            const double t_s = (data.encoder[i].utime - c.start_utime) * 1e-6;
            const auto& ch = data.chamber[static_cast<size_t>(t_s)];
            EXPECT_EQ(ch.cmd_id, 1);
            EXPECT_TRUE(ch.at_setpoint);
            EXPECT_GT(t_s, 70.0 + 60.0);  // 35 K at 30 K/min = 70 s, then the 60 s dwell
            break;
        }
    }
}

// Two units, one setpoint, stopped where the profile finished; in steps of `chunk_us`.
testing::Recorded RunToTheEnd(int64_t chunk_us) {
    RigConfig c = RigConfig::Defaults();
    c.num_units = 2;
    c.thermal.ramp_c_per_min = 60.0;
    return RunProfile<StoppingSink>(c, {.setpoints_c = {35.0}, .dwell_s = 20.0, .rest_s = 5.0},
                                    chunk_us, 3'600'000'000LL)
        .data;
}

TEST(SimBuiltinProfile, EndsAtTheSameSampleWhateverTheBatching) {
    const testing::Recorded a = RunToTheEnd(1'000'000);
    const testing::Recorded b = RunToTheEnd(7'777);
    ASSERT_FALSE(a.chamber.empty());
    ASSERT_EQ(a.gyro.size(), b.gyro.size());
    EXPECT_EQ(a.gyro.back().utime, b.gyro.back().utime);
    EXPECT_EQ(a.gyro.back().gyro_v, b.gyro.back().gyro_v);
    // It ended at a CHAMBER_STATE instant: the last report and the last samples share a time.
    EXPECT_EQ(a.chamber.back().utime, a.gyro.back().utime);
}

}  // namespace
}  // namespace gyrocal::sim
