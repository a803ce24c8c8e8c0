#pragma once
// A synthetic turntable + gyro with known truth for the rotation tests: trapezoid moves
// (accel 100 deg/s^2, cruise 30 deg/s), gyro v = offset + drift * t + S * rate(t) + white noise at
// 100 Hz, a 144000 count/rev encoder at 1 kHz. Events come out merged in time order.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace gyrocal::rotation::testing {

inline constexpr int64_t kT0Utime = 1'000'000'000'000'000;

struct RigSpec {
    double sensitivity_v_per_dps = 6e-3;  // [V/(deg/s)] truth
    double offset_v = 2.5;                // [V] at t = 0
    double drift_v_per_s = 2e-5;          // [V/s] slow offset drift
    double noise_v = 2e-3;                // [V] rms, per 100 Hz sample
    double noise_rho = 0.0;               // [1] AR(1) correlation of successive samples (LPF)
    double temp_c = 30;                   // [degC]
    int32_t counts_per_rev = 144000;
    double gyro_hz = 100, encoder_hz = 1000;
    double accel_dps2 = 100, cruise_dps = 30;
    uint64_t seed = 1;
};

struct Move {
    double start_s;    // [s] from kT0Utime
    double angle_deg;  // signed
};

struct Event {
    bool is_gyro = true;
    int64_t utime = 0;
    int64_t seq = 0;
    double gyro_v = 0, temp_c = 0;  // gyro
    int64_t counts = 0;             // encoder
};

inline double MoveDuration(const RigSpec& r, double angle_deg) {
    const double a = std::fabs(angle_deg), ta = r.cruise_dps / r.accel_dps2;
    const double da = 0.5 * r.accel_dps2 * ta * ta;
    if (a <= 2 * da) return 2 * std::sqrt(a / r.accel_dps2);  // triangle profile
    return 2 * ta + (a - 2 * da) / r.cruise_dps;
}

// Angle [deg] and rate [deg/s] of one move at time t.
inline void MoveState(const RigSpec& r, const Move& m, double t, double& angle, double& rate) {
    const double sgn = m.angle_deg >= 0 ? 1 : -1, a = std::fabs(m.angle_deg), acc = r.accel_dps2;
    double v = r.cruise_dps, ta = v / acc, da = 0.5 * acc * ta * ta;
    if (a <= 2 * da) {
        ta = std::sqrt(a / acc);
        v = acc * ta;
        da = a / 2;
    }
    const double tc = (a - 2 * da) / v, x = t - m.start_s;
    if (x <= 0) {
        angle = rate = 0;
    } else if (x < ta) {
        angle = 0.5 * acc * x * x;
        rate = acc * x;
    } else if (x < ta + tc) {
        angle = da + v * (x - ta);
        rate = v;
    } else if (x < 2 * ta + tc) {
        const double rem = 2 * ta + tc - x;
        angle = a - 0.5 * acc * rem * rem;
        rate = acc * rem;
    } else {
        angle = a;
        rate = 0;
    }
    angle *= sgn;
    rate *= sgn;
}

inline std::vector<Event> Generate(const RigSpec& r, const std::vector<Move>& moves,
                                   double duration_s) {
    std::mt19937_64 rng(r.seed);
    std::normal_distribution<double> g(0, 1);
    auto table = [&](double t, double& angle, double& rate) {
        angle = rate = 0;
        for (const Move& m : moves) {
            double a, v;
            MoveState(r, m, t, a, v);
            angle += a;
            rate += v;
        }
    };
    std::vector<Event> out;
    const int64_t gyro_us = static_cast<int64_t>(std::llround(1e6 / r.gyro_hz));
    const int64_t enc_us = static_cast<int64_t>(std::llround(1e6 / r.encoder_hz));
    const int64_t end_us = static_cast<int64_t>(duration_s * 1e6);
    int64_t tg = 0, te = 0, kg = 0, ke = 0;
    // AR(1) x_k = rho x_{k-1} + sqrt(1 - rho^2) sigma e_k: stationary rms sigma.
    double ar = r.noise_v * g(rng);
    while (tg <= end_us || te <= end_us) {
        if (te <= tg && te <= end_us) {
            double angle, rate;
            table(te * 1e-6, angle, rate);
            Event e;
            e.is_gyro = false;
            e.utime = kT0Utime + te;
            e.seq = ke++;
            e.counts = static_cast<int64_t>(std::floor(angle / 360.0 * r.counts_per_rev));
            out.push_back(e);
            te += enc_us;
        } else if (tg <= end_us) {
            double angle, rate;
            const double t = tg * 1e-6;
            table(t, angle, rate);
            Event e;
            e.utime = kT0Utime + tg;
            e.seq = kg++;
            ar = r.noise_rho * ar + std::sqrt(1 - r.noise_rho * r.noise_rho) * r.noise_v * g(rng);
            e.gyro_v = r.offset_v + r.drift_v_per_s * t + r.sensitivity_v_per_dps * rate + ar;
            e.temp_c = r.temp_c + 0.05 * g(rng);
            out.push_back(e);
            tg += gyro_us;
        } else {
            break;
        }
    }
    return out;
}

// Standard uncertainty of S for white noise (derivation in rotation_estimator.hpp): integral
// noise sigma^2 dt T_int plus the offset's sigma/sqrt(n1 + n2) over T_int (equal rest windows,
// the offset line at the centre weighs each mean 1/2); encoder quantization is negligible
// (1 count = 0.0025 deg of 90).
inline double ExpectedSensitivityStderr(const RigSpec& r, double angle_deg, double guard_s,
                                        double rest_s) {
    const double dt = 1.0 / r.gyro_hz;
    const double t_int = MoveDuration(r, angle_deg) + 2 * guard_s;
    const double n_rest = 2 * rest_s * r.gyro_hz;
    const double var_i =
        r.noise_v * r.noise_v * dt * t_int + t_int * t_int * r.noise_v * r.noise_v / n_rest;
    return std::sqrt(var_i) / std::fabs(angle_deg);
}

}  // namespace gyrocal::rotation::testing
