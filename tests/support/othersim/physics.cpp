#include "tests/support/othersim/physics.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::othersim {

namespace {
constexpr double kPi = 3.14159265358979323846;
double X(double die_c) { return (die_c - 25.0) / 50.0; }
}  // namespace

double UnitTruth::OffsetV(double die_c) const {
    const double x = X(die_c);
    return null_v + a1 * x + a2 * x * x + a3 * x * x * x +
           bend_v * std::exp(-(die_c + 40.0) / bend_c);
}

double UnitTruth::SensitivityVPerDps(double die_c) const {
    const double x = X(die_c);
    return s0 * (1.0 + b1 * x + b2 * x * x + b3 * x * x * x);
}

double UnitTruth::DieFromTempV(double temp_v) const {
    return 25.0 + (temp_v - temp_v_at_25c) / temp_v_per_c;
}

double UnitTruth::DieFromMeasuredC(double temp_c, double v_at_25c, double v_per_c) const {
    return DieFromTempV(v_at_25c + v_per_c * (temp_c - 25.0));
}

std::vector<UnitTruth> DrawUnits(const Options& o) {
    // Its own stream, so that noise options never move the units.
    std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ull + 17);
    std::normal_distribution<double> n(0.0, 1.0);
    const SpreadOptions& s = o.spread;
    std::vector<UnitTruth> units;
    for (const std::string& id : o.SensorIds()) {
        UnitTruth u;
        u.sensor_id = id;
        u.null_v = 2.5 + s.null_sd_v * n(rng);
        u.a1 = s.slope_sd_v * n(rng);
        u.a2 = s.curve_sd_v * n(rng);
        u.a3 = s.cubic_sd_v * n(rng);
        u.bend_v = s.cold_bend_sd_v * n(rng);
        u.bend_c = s.cold_bend_c;
        u.s0 = s.sens_nominal_v_per_dps * (1.0 + s.sens_sd_frac * n(rng));
        u.b1 = s.sens_slope_sd_frac * n(rng);
        u.b2 = s.sens_curve_sd_frac * n(rng);
        u.b3 = s.sens_cubic_sd_frac * n(rng);
        u.temp_v_per_c = 0.009 * (1.0 + s.temp_gain_sd_frac * n(rng));
        u.temp_v_at_25c = 2.5 + 0.009 * s.temp_offset_sd_c * n(rng);
        u.self_heating_c = o.thermal.self_heating_c * (1.0 + 0.1 * n(rng));
        units.push_back(u);
    }
    return units;
}

double RateNoise::OuAvar(double q, double t_s, double tau_s) {
    const double r = tau_s / t_s;
    return q * q * (2.0 * r - 3.0 + 4.0 * std::exp(-r) - std::exp(-2.0 * r)) / (r * r);
}

double RateNoise::BankLevelPerUnitSigma() {
    double log_sum = 0;
    int n = 0;
    for (double tau = 3.0; tau <= 300.0; tau *= 1.25) {
        double avar = 0;
        for (double t : kOuTauS) avar += OuAvar(1.0, t, tau);
        log_sum += 0.5 * std::log(avar);
        ++n;
    }
    return std::exp(log_sum / n);
}

double RateNoise::TheoryAdevDps(const NoiseOptions& o, double tau_s) {
    const double q = o.flicker_dps / BankLevelPerUnitSigma();
    double avar = o.white_dps_rthz * o.white_dps_rthz / tau_s;
    for (double t : kOuTauS) avar += OuAvar(q, t, tau_s);
    avar += o.rrw_dps_rts * o.rrw_dps_rts * tau_s / 3.0;
    return std::sqrt(avar);
}

RateNoise::RateNoise(const NoiseOptions& o, double fs, uint64_t seed) : rng_(seed) {
    const double dt = 1.0 / fs;
    white_sd_ = o.white_dps_rthz * std::sqrt(fs);
    rw_step_ = o.rrw_dps_rts * std::sqrt(dt);
    const double q = o.flicker_dps / BankLevelPerUnitSigma();
    for (size_t k = 0; k < kOuTauS.size(); ++k) {
        phi_[k] = std::exp(-dt / kOuTauS[k]);
        drive_[k] = q * std::sqrt(1.0 - phi_[k] * phi_[k]);
        state_[k] = q * normal_(rng_);
    }
}

double RateNoise::Next() {
    double v = white_sd_ * normal_(rng_);
    for (size_t k = 0; k < state_.size(); ++k) {
        state_[k] = phi_[k] * state_[k] + drive_[k] * normal_(rng_);
        v += state_[k];
    }
    rw_ += rw_step_ * normal_(rng_);
    return v + rw_;
}

Chamber::Chamber(const ThermalOptions& o, double start_c, uint64_t seed)
    : o_(o), x_(start_c), omega_(2.0 * kPi / o.chamber_period_s), rng_(seed) {
    wander_ = o.air_wander_c * normal_(rng_);
}

double Chamber::Advance(double dt_s, double reference_c) {
    // Semi-implicit Euler: stable for omega dt << 1 (here < 0.03).
    const double acc =
        omega_ * omega_ * (reference_c - x_) - 2.0 * o_.chamber_damping * omega_ * v_;
    v_ += acc * dt_s;
    x_ += v_ * dt_s;
    const double phi = std::exp(-dt_s / o_.air_wander_tau_s);
    wander_ = phi * wander_ + o_.air_wander_c * std::sqrt(1.0 - phi * phi) * normal_(rng_);
    return air_c();
}

void ThermalPath::Advance(const ThermalOptions& o, double self_heating_c, double air_c,
                          double dt_s) {
    auto step = [dt_s](double& state, double target, double tau_s) {
        if (tau_s <= 0) {
            state = target;
            return;
        }
        state = target + (state - target) * std::exp(-dt_s / tau_s);
    };
    step(board_c, air_c, o.board_tau_s);
    step(die_c, board_c + self_heating_c, o.die_tau_s);
    step(line_c, die_c, o.temp_line_tau_s);
}

double Move::Duration() const {
    const double th = std::abs(angle_deg), w = rate_dps, a = accel_dps2;
    if (th >= w * w / a) return 2.0 * w / a + (th - w * w / a) / w;
    return 2.0 * std::sqrt(th / a);
}

double Move::RateAt(double t) const {
    const double d = Duration();
    if (t <= 0 || t >= d) return 0.0;
    const double th = std::abs(angle_deg), a = accel_dps2;
    const double w = th >= rate_dps * rate_dps / a ? rate_dps : std::sqrt(th * a);
    const double sign = angle_deg < 0 ? -1.0 : 1.0;
    const double ta = w / a;
    if (t < ta) return sign * a * t;
    if (t > d - ta) return sign * a * (d - t);
    return sign * w;
}

double Move::AngleAt(double t) const {
    const double d = Duration();
    if (t <= 0) return 0.0;
    if (t >= d) return angle_deg;
    const double th = std::abs(angle_deg), a = accel_dps2;
    const double w = th >= rate_dps * rate_dps / a ? rate_dps : std::sqrt(th * a);
    const double sign = angle_deg < 0 ? -1.0 : 1.0;
    const double ta = w / a;
    double ang;
    if (t < ta)
        ang = 0.5 * a * t * t;
    else if (t > d - ta)
        ang = th - 0.5 * a * (d - t) * (d - t);
    else
        ang = 0.5 * a * ta * ta + w * (t - ta);
    return sign * ang;
}

}  // namespace gyrocal::othersim
