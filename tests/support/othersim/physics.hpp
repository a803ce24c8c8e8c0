#pragma once
// othersim's physics: the units' truth curves, the rate noise bank, the chamber and the two-node
// thermal path, the table's move profile. See options.hpp for the design as a whole.
#include <array>
#include <random>
#include <string>
#include <vector>

#include "tests/support/othersim/options.hpp"

namespace gyrocal::othersim {

// One unit's truth, as functions of its die temperature T [degC], with x = (T - 25) / 50:
//   offset_v(T)      = null_v + a1 x + a2 x^2 + a3 x^3 + bend_v exp(-(T + 40) / bend_c)
//   sensitivity(T)   = s0 (1 + b1 x + b2 x^2 + b3 x^3)
//   temperature line = temp_v_at_25c + temp_v_per_c (T - 25)   (read through its lag and ADC)
// The exponential bend is not a polynomial: no degree of fit reproduces it exactly.
struct UnitTruth {
    std::string sensor_id;
    double null_v = 2.5, a1 = 0, a2 = 0, a3 = 0, bend_v = 0, bend_c = 15;  // [V], [degC]
    double s0 = 0.006, b1 = 0, b2 = 0, b3 = 0;                             // [V/(deg/s)], [1]
    double temp_v_at_25c = 2.5;                                            // [V]
    double temp_v_per_c = 0.009;                                           // [V/degC]
    double self_heating_c = 1.2;                                           // [degC]
    double OffsetV(double die_c) const;
    double SensitivityVPerDps(double die_c) const;
    // The die temperature at which the unit's temperature line reads temp_v.
    double DieFromTempV(double temp_v) const;
    // The die temperature behind a temp_c that the pipeline computed from the temperature line
    // with its own transfer (CSV import default: 2.5 V at 25 degC, 9 mV/K).
    double DieFromMeasuredC(double temp_c, double v_at_25c = 2.5, double v_per_c = 0.009) const;
};

// Units drawn from the spread (a stream of its own: the noise never changes the units).
std::vector<UnitTruth> DrawUnits(const Options& o);

// Rate noise of one unit [deg/s]: white + a bank of OU processes (flicker) + random walk.
class RateNoise {
public:
    static constexpr std::array<double, 8> kOuTauS = {0.5,  1.5,   4.5,   13.5,
                                                      40.5, 121.5, 364.5, 1093.5};
    RateNoise(const NoiseOptions& o, double sample_rate_hz, uint64_t seed);
    double Next();
    // The flat Allan level of the bank with unit component sigma: the geometric mean of its Allan
    // deviation over 3..300 s (where it is flat within a few %).
    static double BankLevelPerUnitSigma();
    // Allan variance [(deg/s)^2] of an OU process of sigma q and correlation time t_s at tau_s:
    // q^2 (t/tau)^2 (2 tau/t - 3 + 4 exp(-tau/t) - exp(-2 tau/t)).
    static double OuAvar(double q, double t_s, double tau_s);
    // What the configured noise has in theory at tau (white + bank + random walk).
    static double TheoryAdevDps(const NoiseOptions& o, double tau_s);

private:
    std::mt19937_64 rng_;
    std::normal_distribution<double> normal_{0.0, 1.0};
    double white_sd_ = 0, rw_step_ = 0, rw_ = 0;
    std::array<double, 8> phi_{}, drive_{}, state_{};
};

// The chamber air: a controller whose response to its reference is second order (natural period
// chamber_period_s, damping chamber_damping < 1 overshoots), plus an OU wander.
class Chamber {
public:
    Chamber(const ThermalOptions& o, double start_c, uint64_t seed);
    double Advance(double dt_s, double reference_c);  // [degC] the air after dt_s
    double air_c() const { return x_ + wander_; }

private:
    ThermalOptions o_;
    double x_, v_ = 0, wander_ = 0, omega_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> normal_{0.0, 1.0};
};

// A unit's two thermal nodes and its temperature line (exact first-order steps).
struct ThermalPath {
    double board_c = 25, die_c = 25, line_c = 25;
    void Advance(const ThermalOptions& o, double self_heating_c, double air_c, double dt_s);
};

// A trapezoidal move of `angle_deg` (signed) at cruise rate w and acceleration a.
struct Move {
    double angle_deg = 0, rate_dps = 45, accel_dps2 = 90;
    double Duration() const;
    double AngleAt(double t_s) const;  // [deg] 0 before, angle_deg after
    double RateAt(double t_s) const;   // [deg/s]
    // [s] the middle of the cruise (or of the move, for a triangular profile)
    double CruiseMiddle() const { return 0.5 * Duration(); }
};

}  // namespace gyrocal::othersim
