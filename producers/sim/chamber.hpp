#pragma once
// The temperature chamber's air. A ramp reference moves toward the setpoint at most at the
// ramp-rate limit (the command's, capped by the chamber's own); the air follows the reference
// through a first-order lag air_tau_s (settling), plus a small Ornstein-Uhlenbeck fluctuation of
// the chamber's control. Orders it cannot carry out are refused with a reason, never half-applied.
#include <cstdint>
#include <string>

#include "producers/sim/config.hpp"
#include "producers/sim/rng.hpp"

namespace gyrocal::sim {

class ChamberModel {
public:
    ChamberModel(const ThermalConfig& config, uint64_t seed);

    // Accepts a new setpoint; returns "" when accepted, else why it was refused (state unchanged).
    // ramp_c_per_min <= 0 means the chamber's own limit; faster requests are capped to it.
    std::string Command(int64_t cmd_id, double setpoint_c, double ramp_c_per_min);
    // Advances the air by dt_s seconds (dt_s > 0).
    void Advance(double dt_s);

    double setpoint_c() const { return setpoint_c_; }
    double reference_c() const { return reference_c_; }
    double air_c() const { return air_smooth_c_ + fluctuation_c_; }
    bool at_setpoint() const;
    int64_t cmd_id() const { return cmd_id_; }
    double ramp_c_per_s() const { return ramp_c_per_s_; }

private:
    ThermalConfig config_;
    Rng rng_;
    double setpoint_c_;
    double reference_c_;
    double air_smooth_c_;
    double fluctuation_c_ = 0.0;
    double ramp_c_per_s_;
    int64_t cmd_id_ = -1;
    double last_dt_s_ = -1.0;
    double air_alpha_ = 0.0;
    double noise_phi_ = 0.0;
    double noise_drive_ = 0.0;
};

}  // namespace gyrocal::sim
