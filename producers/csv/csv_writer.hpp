#pragma once
// Writing samples back to the measured-data CSV format (gyrocal-csv-record): the round-trip
// and export side of the parser. Header:
//   time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,encoder_deg,chamber_c,time_since_power_s
// time_s = (utime - time_origin_utime) / 1e6 printed with exactly 6 decimals (the microsecond
// is exact: integer arithmetic, no floating point); volts and degrees in the shortest form
// that reads back to the same double (so a round trip is exact); an empty field where a value
// is unknown (NaN supply, no encoder or chamber reading yet, no power-on time known).
// time_since_power_s = (utime - power_on_utime) / 1e6, exact like time_s.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "gyrocal/gyro_sample_t.hpp"

namespace gyrocal::csv {

inline constexpr const char* kRecordHeader =
    "time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,encoder_deg,chamber_c,time_since_power_s";

// "-1.000001" for utime_us = -1000001: exact decimal seconds.
std::string FormatTimeS(int64_t utime_us);
// Shortest decimal that reads back to the same double; "" for NaN/inf.
std::string FormatValue(double v);

// The value of a quantity in force at a time: the latest reading with utime <= the asked
// time. Readings may arrive slightly out of order relative to the samples (different
// channels); only the newest kKeep are kept.
class LatestAt {
public:
    void Add(int64_t utime, double value);
    std::optional<double> At(int64_t utime) const;

private:
    static constexpr size_t kKeep = 4096;
    std::map<int64_t, double> readings_;
};

// One output line (no newline) for a gyro sample.
std::string FormatRecordRow(const gyro_sample_t& s, int64_t time_origin_utime,
                            std::optional<double> encoder_deg, std::optional<double> chamber_c,
                            std::optional<int64_t> power_on_utime = std::nullopt);

}  // namespace gyrocal::csv
