#include "producers/sim/chamber.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gyrocal::sim {

ChamberModel::ChamberModel(const ThermalConfig& config, uint64_t seed)
    : config_(config),
      rng_(seed, kStreamChamber),
      setpoint_c_(config.start_temp_c),
      reference_c_(config.start_temp_c),
      air_smooth_c_(config.start_temp_c),
      ramp_c_per_s_(config.ramp_c_per_min / 60.0) {
    fluctuation_c_ = config_.air_noise_c * rng_.Normal();  // stationary start
}

std::string ChamberModel::Command(int64_t cmd_id, double setpoint_c, double ramp_c_per_min) {
    std::ostringstream why;
    if (!std::isfinite(setpoint_c) || setpoint_c < config_.min_setpoint_c ||
        setpoint_c > config_.max_setpoint_c) {
        why << "chamber cmd_id " << cmd_id << ": setpoint_c " << setpoint_c
            << " outside the chamber's range " << config_.min_setpoint_c << " .. "
            << config_.max_setpoint_c << " degC";
        return why.str();
    }
    if (!std::isfinite(ramp_c_per_min)) {
        why << "chamber cmd_id " << cmd_id << ": ramp_rate_c_per_min is not finite";
        return why.str();
    }
    const double limit = config_.ramp_c_per_min;
    ramp_c_per_s_ = (ramp_c_per_min <= 0.0 ? limit : std::min(ramp_c_per_min, limit)) / 60.0;
    setpoint_c_ = setpoint_c;
    cmd_id_ = cmd_id;
    return "";
}

void ChamberModel::Advance(double dt_s) {
    if (dt_s != last_dt_s_) {  // the step is nearly always the sample period: cache the factors
        last_dt_s_ = dt_s;
        air_alpha_ = 1.0 - std::exp(-dt_s / config_.air_tau_s);
        noise_phi_ = std::exp(-dt_s / config_.air_noise_tau_s);
        noise_drive_ = config_.air_noise_c * std::sqrt(1.0 - noise_phi_ * noise_phi_);
    }
    const double max_step = ramp_c_per_s_ * dt_s;
    reference_c_ += std::clamp(setpoint_c_ - reference_c_, -max_step, max_step);
    air_smooth_c_ += (reference_c_ - air_smooth_c_) * air_alpha_;
    fluctuation_c_ = noise_phi_ * fluctuation_c_ + noise_drive_ * rng_.Normal();
}

bool ChamberModel::at_setpoint() const {
    return std::abs(air_c() - setpoint_c_) <= config_.setpoint_tolerance_c;
}

}  // namespace gyrocal::sim
