#pragma once
// A validated row -> the messages a real rig would have sent for it:
// - always one gyro_sample_t for GYRO_<sensor_id>: seq counts per sensor from 0, volts as
//   given, has_adc false (a CSV carries no ADC codes), supply_v NaN when not measured;
// - an encoder_sample_t when the row has encoder_deg and its time_s is later than the last
//   encoder reading (interleaved sensors repeat the same table angle at the same time; the
//   encoder is one device and publishes once per distinct time);
//   counts = round(angle_deg * counts_per_rev / 360), angle_deg exactly as given;
// - a chamber_state_t when the row has chamber_c and at least 1 s of data time has passed
//   since the last one (a chamber reports about once a second; more would flood CHAMBER_STATE).
//   The file has no setpoint: setpoint_c is NaN, cmd_id -1, at_setpoint false.
// - a power_state_t for POWER_<sensor_id> when the row has time_since_power_s (power_on_utime =
//   utime - time_since_power_s) on the sensor's first such row, whenever the power-on time moves
//   by more than kPowerOnToleranceUs (a new power cycle), and at least every kPowerRepeatS of
//   data time (for late joiners).
// The caller supplies utime (from time_s, or the wall clock for a live stream).
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "producers/csv/row_parser.hpp"

namespace gyrocal::csv {

inline constexpr int64_t kDefaultStartUtime = 1'000'000'000'000'000;  // [us] 1e15
inline constexpr int32_t kDefaultEncoderCountsPerRev = 4 * 5000;      // [count/rev] quadrature
inline constexpr const char* kEncoderId = "TABLE";
inline constexpr double kChamberPeriodS = 1.0;  // [s] of data time
inline constexpr double kPowerRepeatS = 10.0;   // [s] of data time
// [us] a time_since_power_s written with fewer decimals moves the power-on time by its rounding.
inline constexpr int64_t kPowerOnToleranceUs = 1000;
inline constexpr const char* kPowerSource = "csv time_since_power_s";

struct RowMessages {
    gyro_sample_t gyro;
    std::optional<encoder_sample_t> encoder;
    std::optional<chamber_state_t> chamber;
    std::optional<power_state_t> power;  // before the gyro sample, when sent
};

class MessageBuilder {
public:
    explicit MessageBuilder(int32_t encoder_counts_per_rev = kDefaultEncoderCountsPerRev);

    // utime [us] of this row. Builds the messages and advances the per-sensor/encoder/chamber
    // state; every message is complete when returned.
    RowMessages Build(const CsvRow& row, int64_t utime);

private:
    int32_t counts_per_rev_;
    std::map<std::string, int64_t> next_seq_;
    int64_t encoder_seq_ = 0;
    int64_t chamber_seq_ = 0;
    std::optional<double> last_encoder_time_s_;
    std::optional<double> last_chamber_time_s_;
    struct Power {
        int64_t power_on_utime;
        int64_t sent_utime;
    };
    std::map<std::string, Power> power_;
    int64_t power_seq_ = 0;
};

// [us] utime of a row replayed with stream time.
inline int64_t StreamUtime(int64_t start_utime, double time_s) {
    return start_utime + TimeUs(time_s);
}

}  // namespace gyrocal::csv
