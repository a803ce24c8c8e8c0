#pragma once
// The truth of one simulated gyro unit: how its null offset and sensitivity depend on its DIE
// temperature, drawn once per unit from a seeded spread.
//
//   offset_v(T)              = o0 + o1*dT + o2*dT^2            dT = T_die - 25 degC
//   sensitivity_v_per_dps(T) = s0 + s1*dT + s2*dT^2
//
// o1 (a few tenths of mV/K) and o2 (a few uV/K^2, so that over -40..85 degC the curve is visibly
// bent) have random signs; s1, s2 are drawn as fractions of s0 (a few %/100 K). The unit's
// temperature sensor reads its die temperature with an offset of its own, and its package has
// its own thermal time constant (spread about the configured one).
#include <array>
#include <string>

#include "producers/sim/config.hpp"
#include "producers/sim/rng.hpp"

namespace gyrocal::sim {

inline constexpr double kTruthT0C = 25.0;  // [degC] reference temperature of the truth curves

struct UnitTruth {
    std::string sensor_id;
    std::array<double, 3> offset_coeffs{};       // [V, V/K, V/K^2] about kTruthT0C, die temp
    std::array<double, 3> sensitivity_coeffs{};  // [V/(deg/s), ../K, ../K^2] about kTruthT0C
    double temp_sensor_offset_c = 0.0;           // [degC] sensor reads die + this (after its lag)
    double package_tau_s = 0.0;                  // [s] this unit's die lag behind the air

    double OffsetV(double die_c) const;
    double SensitivityVPerDps(double die_c) const;
};

// Draws unit `unit_index` (0-based) of `config` from its own random stream.
UnitTruth DrawUnit(const RigConfig& config, int unit_index, const std::string& sensor_id);

}  // namespace gyrocal::sim
