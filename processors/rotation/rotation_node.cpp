#include "rotation_node.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "bus/channels.hpp"
#include "gyrocal/sensitivity_point_t.hpp"

namespace gyrocal {

namespace {

// The libraries name a config field first ("window_s must be ..."); the option is that name
// with dashes ("--window-s must be ...").
std::string AsOption(std::string message) {
    const size_t end = message.find(' ');
    for (size_t i = 0; i < end && i < message.size(); ++i) {
        if (message[i] == '_') message[i] = '-';
    }
    return "--" + message;
}

constexpr const char* kProcess = "gyrocal-rotation";
}  // namespace

std::string RotationOptions::Validate() const {
    for (const std::string& s : sensors) {
        if (!channels::IsValidSensorId(s))
            return "--sensors: '" + s +
                   "' is not a valid sensor id (1-32 letters, digits, '-', '_')";
    }
    if (encoder_id.empty()) return "--encoder-id must not be empty";
    if (std::string e = estimator.Validate(); !e.empty()) return AsOption(e);
    if (std::string e = move.Validate(); !e.empty()) return AsOption(e);
    return "";
}

RotationNode::RotationNode(const RotationOptions& options)
    : options_(options),
      bus_(BusOptions{options.lcm_url}),
      status_(bus_, kProcess),
      detector_(options.move) {
    // Handlers never let an exception reach LCM: it is counted as a refusal with its text.
    auto guarded = [this](auto fn) {
        return [this, fn](const auto& m, const std::string& ch) {
            try {
                fn(m, ch);
            } catch (const std::exception& e) {
                status_.Reject("internal", ch + ": " + e.what());
            }
        };
    };
    bus_.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        guarded([this](const gyro_sample_t& m, const std::string& ch) { OnGyro(m, ch); }));
    bus_.Subscribe<encoder_sample_t>(
        std::string(channels::kEncoder),
        guarded([this](const encoder_sample_t& m, const std::string&) { OnEncoder(m); }));
    bus_.Subscribe<run_event_t>(
        std::string(channels::kRunEvent),
        guarded([this](const run_event_t& m, const std::string&) { OnRunEvent(m); }));
}

void RotationNode::Run() {
    status_.set_state("running");
    // Malformed payloads (wrong type, hostile array lengths) are counted by the bus as decode
    // errors and never reach a handler; anything else thrown here is a bug and ends the process.
    RunLoop(bus_, status_);
}

rotation::MotionView RotationNode::View() const {
    return rotation::MotionView{detector_.watermark_utime(), detector_.current_start_utime()};
}

void RotationNode::OnGyro(const gyro_sample_t& m, const std::string& channel) {
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
    if (!options_.sensors.empty() && std::find(options_.sensors.begin(), options_.sensors.end(),
                                               *id) == options_.sensors.end()) {
        status_.Reject("unknown sensor", channel + ": sensor '" + *id + "' is not in --sensors");
        return;
    }
    if (!std::isfinite(m.gyro_v) || !std::isfinite(m.temp_c)) {
        // Skipped: the hole it leaves is a sequence gap, so a move around it is rejected.
        status_.Reject("non-finite", channel + ": gyro_v and temp_c must be finite (seq " +
                                         std::to_string(m.seq) + ")");
        return;
    }
    auto it = sensors_.find(*id);
    if (it == sensors_.end()) {
        it = sensors_.emplace(*id, std::make_unique<Sensor>(options_.estimator)).first;
        status_.SetExtra("sensors", static_cast<double>(sensors_.size()));
    }
    Sensor& sensor = *it->second;
    if (sensor.any && m.utime <= sensor.newest_utime) {
        status_.Reject("out-of-order", channel + ": utime " + std::to_string(m.utime) +
                                           " is not after " + std::to_string(sensor.newest_utime));
        return;
    }
    sensor.any = true;
    sensor.newest_utime = m.utime;
    sensor.estimator.AddSample(rotation::Sample{m.utime, m.seq, m.gyro_v, m.temp_c});
    PollAndPublish(*id, sensor);
}

void RotationNode::OnEncoder(const encoder_sample_t& m) {
    if (m.encoder_id != options_.encoder_id) {
        status_.Reject("unknown encoder", "ENCODER: encoder_id '" + m.encoder_id +
                                              "' is not --encoder-id '" + options_.encoder_id +
                                              "'");
        return;
    }
    if (m.counts_per_rev <= 0) {
        status_.Reject("bad encoder", "ENCODER: counts_per_rev must be > 0, got " +
                                          std::to_string(m.counts_per_rev));
        return;
    }
    if (any_encoder_ && m.utime <= last_encoder_utime_) {
        status_.Reject("out-of-order", "ENCODER: utime " + std::to_string(m.utime) +
                                           " is not after " + std::to_string(last_encoder_utime_));
        return;
    }
    any_encoder_ = true;
    last_encoder_utime_ = m.utime;
    if (auto move = detector_.Feed(motion::EncoderReading{m.utime, m.counts, m.counts_per_rev})) {
        ++moves_;
        status_.SetExtra("moves", static_cast<double>(moves_));
        for (auto& [id, sensor] : sensors_) sensor->estimator.AddMove(*move);
    }
    for (auto& [id, sensor] : sensors_) PollAndPublish(id, *sensor);
}

void RotationNode::OnRunEvent(const run_event_t& m) {
    if (m.event == "start") {
        run_id_ = m.run_id;
    } else if (m.event == "stop" || m.event == "abort") {
        run_id_.clear();
    } else if (m.event != "setpoint" && m.event != "rotation") {
        status_.Reject("unknown event", "RUN_EVENT: event '" + m.event +
                                            "' is not start, setpoint, rotation, stop or abort");
    }
}

void RotationNode::PollAndPublish(const std::string& id, Sensor& sensor) {
    for (const rotation::Point& p : sensor.estimator.Poll(View())) {
        sensitivity_point_t msg;
        msg.utime = p.end_utime;
        msg.sensor_id = id;
        msg.run_id = run_id_;
        msg.rotation_id = p.rotation_id;
        msg.start_utime = p.start_utime;
        msg.end_utime = p.end_utime;
        msg.first_seq = p.first_seq;
        msg.last_seq = p.last_seq;
        msg.n_samples = p.n_samples;
        msg.direction = p.direction;
        msg.temp_c = p.temp_c;
        msg.encoder_angle_deg = p.encoder_angle_deg;
        msg.offset_v = p.offset_v;
        msg.offset_stderr_v = p.offset_stderr_v;
        msg.integral_v_s = p.integral_v_s;
        msg.sensitivity_v_per_dps = p.sensitivity_v_per_dps;
        msg.sensitivity_stderr_v_per_dps = p.sensitivity_stderr_v_per_dps;
        msg.accepted = p.accepted;
        msg.reject_reason = p.reject_reason;
        bus_.Publish(channels::Sensitivity(id), msg);
        if (p.accepted) {
            ++accepted_;
        } else {
            ++refused_;
            status_.Reject("rotation rejected", "SENSITIVITY_" + id + ": " + p.reject_reason);
        }
        status_.SetExtra("points_accepted", static_cast<double>(accepted_));
        status_.SetExtra("points_rejected", static_cast<double>(refused_));
    }
}

}  // namespace gyrocal
