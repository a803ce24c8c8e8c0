#pragma once
// The gyro module's temperature output, volts <-> degC: a straight line through v_at_25c with
// slope v_per_c (ADXRS610/613 datasheets: 2.5 V at 25 degC, 9 mV/K, which is 9 mV/degC; the
// myGyro61xEB boards pass it through unchanged). temp_c = 25 + (temp_v - v_at_25c) / v_per_c.
// The simulated rig writes its temperature line with it, the measured-data sources read temp_v
// back with it.
#include <optional>
#include <string>

namespace gyrocal::sensor {

struct TempTransfer {
    double v_at_25c = 2.5;   // [V] output at 25 degC
    double v_per_c = 0.009;  // [V/degC] slope
    double TempC(double temp_v) const { return 25.0 + (temp_v - v_at_25c) / v_per_c; }
    double TempV(double temp_c) const { return v_at_25c + v_per_c * (temp_c - 25.0); }
};

// Presets by module: "610" (myGyro610EB / ADXRS610) and "613" (myGyro613EB / ADXRS613).
// nullopt for any other name.
std::optional<TempTransfer> PresetTransfer(const std::string& preset);
inline constexpr const char* kValidPresets = "610 or 613";

// Empty when valid, otherwise why (names the option and the valid range).
std::string ValidateTransfer(const TempTransfer& t);

}  // namespace gyrocal::sensor
