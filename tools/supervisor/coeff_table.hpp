#pragma once
// The tables `gyrocal calibrate` prints at the end: the coefficient sets as fitted, and — for a
// simulated run — the fitted curves against the rig's truth sidecar.
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "gyrocal/coeff_set_t.hpp"

namespace gyrocal::supervisor {

// One block per sensor: method, T0, valid range, residual RMS, point count, every term with its
// coefficient and 1-sigma, for offset and sensitivity. `labels` (per sensor, "" = none): what
// makes a set not a complete final calibration, printed on its header line.
std::string FormatCoeffTable(const std::map<std::string, coeff_set_t>& coeffs,
                             const std::map<std::string, std::string>& labels = {});

// Fitted versus true, per sensor, at die temperatures across the calibrated range. The truth
// curves are functions of the die temperature; the fit is on the sensor's reported temperature,
// which at rest reads die + temp_sensor_offset_c. So fitted(T_die + offset) is compared with
// true(T_die): the offset error in mV and as rate error in deg/s (divided by the true
// sensitivity), the sensitivity error in percent. Throws std::runtime_error on a truth file of
// another format.
std::string FormatTruthComparison(const std::map<std::string, coeff_set_t>& coeffs,
                                  const nlohmann::json& truth);

}  // namespace gyrocal::supervisor
