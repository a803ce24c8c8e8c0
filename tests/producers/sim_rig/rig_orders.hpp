#pragma once
// The orders the simulated rig's tests give it, in-process and as a process.
#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"

namespace gyrocal::testing {

// Order 1: turn the table +90 deg at its default rate and acceleration (the zeros).
inline turntable_cmd_t QuarterTurn() {
    turntable_cmd_t move{};
    move.cmd_id = 1;
    move.move_deg = 90.0;
    return move;
}

// Order 6: a chamber setpoint the rig refuses (200 degC, outside its -45..90).
inline chamber_cmd_t ImpossibleChamberOrder() {
    chamber_cmd_t bad{};
    bad.cmd_id = 6;
    bad.setpoint_c = 200.0;
    return bad;
}

}  // namespace gyrocal::testing
