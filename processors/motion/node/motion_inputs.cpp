#include "processors/motion/node/motion_inputs.hpp"

#include <algorithm>
#include <utility>

#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::motion::node {

bool StreamTime::InOrder(int64_t utime, const std::string& stream,
                         process::StatusReporter& status) const {
    if (any_ && utime <= newest_utime_) {
        status.Reject("out-of-order", stream + ": utime " + std::to_string(utime) +
                                          " is not after " + std::to_string(newest_utime_));
        return false;
    }
    return true;
}

MotionInputs::MotionInputs(bus::Bus& bus, process::StatusReporter& status,
                           std::vector<std::string> sensors, std::string encoder_id,
                           Handler& handler)
    : status_(status),
      sensors_(std::move(sensors)),
      encoder_id_(std::move(encoder_id)),
      handler_(handler) {
    bus.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        Guarded(status_, [this](const gyro_sample_t& m, const std::string& ch) { OnGyro(m, ch); }));
    bus.Subscribe<encoder_sample_t>(
        std::string(channels::kEncoder),
        Guarded(status_, [this](const encoder_sample_t& m, const std::string&) { OnEncoder(m); }));
    bus.Subscribe<run_event_t>(std::string(channels::kRunEvent),
                               Guarded(status_, [this](const run_event_t& m, const std::string&) {
                                   handler_.OnRunEvent(m);
                               }));
}

void MotionInputs::OnGyro(const gyro_sample_t& m, const std::string& channel) {
    const auto id = channels::SensorOf(channels::kGyroPrefix, channel);
    if (!id) {
        status_.Reject("bad channel", channel + ": not GYRO_<sensor id>");
        return;
    }
    if (m.sensor_id != *id) {
        status_.Reject("sensor mismatch",
                       channel + ": sensor_id '" + m.sensor_id + "' does not match the channel");
        return;
    }
    if (!sensors_.empty() && std::find(sensors_.begin(), sensors_.end(), *id) == sensors_.end()) {
        status_.Reject("unknown sensor", channel + ": sensor '" + *id + "' is not in --sensors");
        return;
    }
    handler_.OnGyro(*id, m, channel);
}

void MotionInputs::OnEncoder(const encoder_sample_t& m) {
    if (m.encoder_id != encoder_id_) {
        status_.Reject("unknown encoder", "ENCODER: encoder_id '" + m.encoder_id +
                                              "' is not --encoder-id '" + encoder_id_ + "'");
        return;
    }
    if (m.counts_per_rev <= 0) {
        status_.Reject("bad encoder", "ENCODER: counts_per_rev must be > 0, got " +
                                          std::to_string(m.counts_per_rev));
        return;
    }
    if (!encoder_time_.InOrder(m.utime, "ENCODER", status_)) return;
    encoder_time_.Advance(m.utime);
    handler_.OnEncoder(EncoderReading{m.utime, m.counts, m.counts_per_rev});
}

}  // namespace gyrocal::motion::node
