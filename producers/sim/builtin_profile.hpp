#pragma once
// The rig's own procedure, for running without a sequencer (--mode builtin): for each setpoint,
// order the chamber there, wait until the air is at the setpoint, dwell (so the packages settle
// and a plateau detector downstream finds its window), then +move, rest, -move, rest, and on to
// the next setpoint. Driven once per CHAMBER_STATE, i.e. in simulated time only, so a run is the
// same whatever the wall-clock pacing.
#include <cstdint>
#include <string>
#include <vector>

#include "producers/sim/rig.hpp"

namespace gyrocal::sim {

struct ProfileConfig {
    std::vector<double> setpoints_c = {-10.0, 30.0, 60.0};  // [degC]
    double dwell_s = 1500.0;                                // [s] at setpoint before the rotations
    double rest_s = 30.0;                                   // [s] still after each move
    double move_deg = 90.0;                                 // [deg] rotation, done + then -
    static ProfileConfig Defaults() { return {}; }
};

// Parses "-10,30,60"; throws ConfigError naming --profile and what is valid (1..64 finite numbers
// inside the chamber's setpoint range).
std::vector<double> ParseProfile(const std::string& text, const ThermalConfig& thermal);

class BuiltinProfile {
public:
    explicit BuiltinProfile(ProfileConfig config);
    // Call with each chamber reading; issues the orders due at that time.
    void OnChamber(const ChamberReading& reading, Rig& rig);
    bool done() const { return phase_ == Phase::kDone; }
    int setpoint_index() const { return index_; }

private:
    enum class Phase {
        kStart,
        kRamping,
        kDwell,
        kMovePlus,
        kRestPlus,
        kMoveMinus,
        kRestMinus,
        kDone
    };
    void Enter(Phase phase, int64_t utime);
    // Orders the chamber to setpoint index_ and waits for it (kRamping).
    void OrderSetpoint(Rig& rig, int64_t utime);
    // Orders a turn of `move_deg` and enters `moving` (kMovePlus or kMoveMinus).
    void OrderTurn(Rig& rig, double move_deg, Phase moving, int64_t utime);

    ProfileConfig config_;
    Phase phase_ = Phase::kStart;
    int index_ = 0;
    int64_t phase_start_utime_ = 0;
    int64_t next_table_cmd_id_ = 1;
};

}  // namespace gyrocal::sim
