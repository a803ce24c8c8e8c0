#include "producers/csv/csv_writer.hpp"

#include <charconv>
#include <cmath>
#include <iterator>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::csv {

std::string FormatTimeS(int64_t utime_us) {
    const bool negative = utime_us < 0;
    // Magnitude in unsigned arithmetic so INT64_MIN cannot overflow.
    const uint64_t mag =
        negative ? uint64_t(0) - static_cast<uint64_t>(utime_us) : static_cast<uint64_t>(utime_us);
    return text::Printf("%s%llu.%06llu", negative ? "-" : "",
                        static_cast<unsigned long long>(mag / 1000000),
                        static_cast<unsigned long long>(mag % 1000000));
}

std::string FormatValue(double v) {
    if (!std::isfinite(v)) return "";
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    if (ec != std::errc()) return "";
    return std::string(buf, end);
}

void LatestAt::Add(int64_t utime, double value) {
    readings_[utime] = value;
    while (readings_.size() > kKeep) readings_.erase(readings_.begin());
}

std::optional<double> LatestAt::At(int64_t utime) const {
    auto it = readings_.upper_bound(utime);
    if (it == readings_.begin()) return std::nullopt;
    return std::prev(it)->second;
}

std::string FormatRecordRow(const gyro_sample_t& s, int64_t time_origin_utime,
                            std::optional<double> encoder_deg, std::optional<double> chamber_c,
                            std::optional<int64_t> power_on_utime) {
    std::string line = FormatTimeS(s.utime - time_origin_utime);
    line += ',';
    line += s.sensor_id;
    for (double v : {s.gyro_v, s.temp_v, s.temp_c, s.supply_v}) {
        line += ',';
        line += FormatValue(v);
    }
    line += ',';
    if (encoder_deg) line += FormatValue(*encoder_deg);
    line += ',';
    if (chamber_c) line += FormatValue(*chamber_c);
    line += ',';
    if (power_on_utime && *power_on_utime <= s.utime)
        line += FormatTimeS(s.utime - *power_on_utime);
    return line;
}

}  // namespace gyrocal::csv
