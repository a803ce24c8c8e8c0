#pragma once
// The truth sidecar of a run: what evaluations compare a calibration against, never published on
// any channel. Per unit, the offset and sensitivity curves as polynomials in (T_die - 25 degC),
// where T_die is the DIE temperature (the package-lagged chamber air, before the temperature
// sensor's own lag and offset), also tabulated every 5 degC over -40..85 degC; the sensor's
// offset and the package time constant; the effects and their magnitudes; the seed and the whole
// configuration.
#include <nlohmann/json.hpp>

#include "producers/sim/rig.hpp"

namespace gyrocal::sim {

nlohmann::json ConfigJson(const RigConfig& config);
nlohmann::json TruthJson(const Rig& rig);

}  // namespace gyrocal::sim
