#pragma once
// Channel names, defined once. Per-sensor channels end in _<sensor_id> so that lcm-spy shows
// each unit on its own row; the *_REGEX forms are what multi-sensor subscribers listen to.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::channels {

inline constexpr std::string_view kGyroPrefix = "GYRO_";
inline constexpr std::string_view kPlateauPrefix = "PLATEAU_";
inline constexpr std::string_view kStabilityPrefix = "STABILITY_";  // plateau_state_t
inline constexpr std::string_view kSensitivityPrefix = "SENSITIVITY_";
inline constexpr std::string_view kCoeffsPrefix = "COEFFS_";
inline constexpr std::string_view kRatePrefix = "RATE_";
inline constexpr std::string_view kNoisePrefix = "NOISE_";        // noise_t (Allan deviation)
inline constexpr std::string_view kFitPrefix = "FIT_";            // fit_report_t
inline constexpr std::string_view kPowerPrefix = "POWER_";        // power_state_t
inline constexpr std::string_view kAnalysisPrefix = "ANALYSIS_";  // analysis_t (closed loop)

inline constexpr std::string_view kEncoder = "ENCODER";
inline constexpr std::string_view kChamberCmd = "CHAMBER_CMD";
inline constexpr std::string_view kChamberState = "CHAMBER_STATE";
inline constexpr std::string_view kTurntableCmd = "TURNTABLE_CMD";
inline constexpr std::string_view kRunEvent = "RUN_EVENT";
inline constexpr std::string_view kStatus = "STATUS";
// Flow control of non-real-time sources (lcmtypes/flow): flow_mark_t and flow_ack_t.
inline constexpr std::string_view kFlowMark = "FLOW_MARK";
inline constexpr std::string_view kFlowAck = "FLOW_ACK";

// A sensor id is what follows the prefix of a per-sensor channel: letters, digits, '-' and '_'
// only (LCM subscribes by regular expression; anything else would need escaping), 1..32 chars.
bool IsValidSensorId(std::string_view sensor_id);
// "" when every id is valid, else "<option>: '<id>' is not a valid sensor id (...)".
std::string ValidateSensorIds(const std::vector<std::string>& sensor_ids,
                              const std::string& option);

// Throws std::invalid_argument naming the id and the valid form when it is not valid.
std::string PerSensor(std::string_view prefix, std::string_view sensor_id);

inline std::string Gyro(std::string_view id) { return PerSensor(kGyroPrefix, id); }
inline std::string Plateau(std::string_view id) { return PerSensor(kPlateauPrefix, id); }
inline std::string Stability(std::string_view id) { return PerSensor(kStabilityPrefix, id); }
inline std::string Sensitivity(std::string_view id) { return PerSensor(kSensitivityPrefix, id); }
inline std::string Coeffs(std::string_view id) { return PerSensor(kCoeffsPrefix, id); }
inline std::string Rate(std::string_view id) { return PerSensor(kRatePrefix, id); }
inline std::string Noise(std::string_view id) { return PerSensor(kNoisePrefix, id); }
inline std::string Fit(std::string_view id) { return PerSensor(kFitPrefix, id); }
inline std::string Power(std::string_view id) { return PerSensor(kPowerPrefix, id); }
inline std::string Analysis(std::string_view id) { return PerSensor(kAnalysisPrefix, id); }

// Regex matching every sensor's channel of a prefix, e.g. "GYRO_[A-Za-z0-9_-]+". No prefix is a
// prefix of another, so these never overlap.
std::string AllSensors(std::string_view prefix);

// The sensor id of a per-sensor channel, or nullopt when the channel is not of that prefix.
std::optional<std::string> SensorOf(std::string_view prefix, std::string_view channel);

}  // namespace gyrocal::channels
