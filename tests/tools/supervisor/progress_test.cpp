// The progress line and the time-left estimate of `gyrocal calibrate`.
#include "tools/supervisor/progress.hpp"

#include <gtest/gtest.h>

namespace gyrocal::supervisor {
namespace {

run_event_t Event(const std::string& what, int index) {
    run_event_t e{};
    e.run_id = "r1";
    e.event = what;
    e.setpoint_index = index;
    e.setpoint_c = 10.0 * index;
    return e;
}

TEST(Progress, FractionFollowsSetpointsAndMoves) {
    Progress p(4, 2);
    EXPECT_EQ(p.FractionDone(), 0.0);
    EXPECT_LT(p.EtaS(10), 0) << "no estimate before anything is done";
    p.OnRunEvent(Event("start", -1));
    p.OnRunEvent(Event("setpoint", 1));
    EXPECT_DOUBLE_EQ(p.FractionDone(), 0.25);
    EXPECT_DOUBLE_EQ(p.EtaS(100), 300.0);  // 25 % in 100 s -> 300 s left
    p.OnRunEvent(Event("rotation", 1));    // first move announced: plateau done
    EXPECT_DOUBLE_EQ(p.FractionDone(), (1 + 0.75) / 4);
    p.OnRunEvent(Event("rotation", 1));
    EXPECT_DOUBLE_EQ(p.FractionDone(), (1 + 0.875) / 4);
    p.OnRunEvent(Event("stop", 3));
    EXPECT_DOUBLE_EQ(p.FractionDone(), 1.0);
}

TEST(Progress, LineShowsSensorsStatesAndLosses) {
    Progress p(5, 2);
    p.OnRunEvent(Event("setpoint", 0));
    plateau_state_t s{};
    s.sensor_id = "S01";
    s.state = "averaging";
    s.temp_c = -9.9;
    s.averaging_progress = 0.4;
    p.OnStability(s);
    s.sensor_id = "S02";
    s.state = "settling";
    s.temp_slope_c_per_min = 0.21;
    p.OnStability(s);
    status_t st{};  // value-initialised: lcm-gen types leave scalars uninitialised
    st.process = "gyrocal-recorder";
    st.host = "h";
    st.pid = 1;
    st.seq_gaps = 3;
    st.queue_drops = 1;
    p.OnStatus(st);
    st.seq_gaps = 4;  // a newer heartbeat of the same process replaces, not adds
    p.OnStatus(st);
    const std::string line = p.Line(5.0);
    EXPECT_NE(line.find("setpoint 1/5"), std::string::npos) << line;
    EXPECT_NE(line.find("S01 -9.9 C averaging 40%"), std::string::npos) << line;
    EXPECT_NE(line.find("S02"), std::string::npos) << line;
    EXPECT_NE(line.find("settling +0.21 C/min"), std::string::npos) << line;
    EXPECT_EQ(p.drops(), 5);
    EXPECT_NE(line.find("losses 5"), std::string::npos) << line;
    // A handler's failures (the bus's extra counter) are losses too (issue 27).
    st.num_extra = 2;
    st.extra_names = {"publish_errors", "handler_errors"};
    st.extra_values = {9, 2};
    p.OnStatus(st);
    EXPECT_EQ(p.drops(), 7);
}

}  // namespace
}  // namespace gyrocal::supervisor
