#include "producers/csv/row_messages.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace gyrocal::csv {

MessageBuilder::MessageBuilder(int32_t encoder_counts_per_rev)
    : counts_per_rev_(encoder_counts_per_rev) {}

RowMessages MessageBuilder::Build(const CsvRow& row, int64_t utime) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    RowMessages out;
    gyro_sample_t& g = out.gyro;
    g.utime = utime;
    g.sensor_id = row.sensor_id;
    g.seq = next_seq_[row.sensor_id]++;
    g.gyro_v = row.gyro_v;
    g.temp_v = row.temp_v;
    g.temp_c = row.temp_c;
    g.supply_v = row.supply_v.value_or(nan);
    g.has_adc = false;
    g.gyro_counts = 0;
    g.temp_counts = 0;
    g.supply_counts = -1;

    if (row.encoder_deg && (!last_encoder_time_s_ || row.time_s > *last_encoder_time_s_)) {
        encoder_sample_t e;
        e.utime = utime;
        e.encoder_id = kEncoderId;
        e.seq = encoder_seq_++;
        e.counts = std::llround(*row.encoder_deg * counts_per_rev_ / 360.0);
        e.counts_per_rev = counts_per_rev_;
        e.angle_deg = *row.encoder_deg;
        out.encoder = e;
        last_encoder_time_s_ = row.time_s;
    }
    if (row.chamber_c &&
        (!last_chamber_time_s_ ||
         TimeUs(row.time_s) - TimeUs(*last_chamber_time_s_) >= TimeUs(kChamberPeriodS))) {
        chamber_state_t c;
        c.utime = utime;
        c.seq = chamber_seq_++;
        c.cmd_id = -1;
        c.setpoint_c = nan;
        c.air_c = *row.chamber_c;
        c.at_setpoint = false;
        c.fault = "";
        out.chamber = c;
        last_chamber_time_s_ = row.time_s;
    }
    if (row.time_since_power_s) {
        const int64_t on = utime - TimeUs(*row.time_since_power_s);
        const auto it = power_.find(row.sensor_id);
        if (it == power_.end() ||
            std::llabs(on - it->second.power_on_utime) > kPowerOnToleranceUs ||
            utime - it->second.sent_utime >= TimeUs(kPowerRepeatS)) {
            power_state_t p;
            p.utime = utime;
            p.sensor_id = row.sensor_id;
            p.seq = power_seq_++;
            // A repeat keeps the first value of the cycle, so rounding never moves it.
            p.power_on_utime = it == power_.end() || std::llabs(on - it->second.power_on_utime) >
                                                         kPowerOnToleranceUs
                                   ? on
                                   : it->second.power_on_utime;
            p.source = kPowerSource;
            out.power = p;
            power_[row.sensor_id] = {p.power_on_utime, utime};
        }
    }
    return out;
}

}  // namespace gyrocal::csv
