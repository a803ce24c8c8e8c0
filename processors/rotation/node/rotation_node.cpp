#include "processors/rotation/node/rotation_node.hpp"

#include <cmath>

#include "lcmtypes/channels/channels.hpp"
#include "processors/motion/node/motion_options.hpp"
#include "processors/rotation/node/rotation_message.hpp"

namespace gyrocal::rotation::node {

namespace {
constexpr const char* kProcess = "gyrocal-rotation";
}  // namespace

std::string RotationOptions::Validate() const {
    if (std::string e = motion::node::ValidateInput(sensors, encoder_id); !e.empty()) return e;
    if (std::string e = estimator.Validate(); !e.empty()) return motion::node::AsOption(e);
    if (std::string e = move.Validate(); !e.empty()) return motion::node::AsOption(e);
    return "";
}

RotationNode::RotationNode(const RotationOptions& options)
    : MotionNode(kProcess, options.lcm_url, options.sensors, options.encoder_id),
      options_(options),
      detector_(options.move) {}

rotation::MotionView RotationNode::View() const {
    return rotation::MotionView{detector_.watermark_utime(), detector_.current_start_utime()};
}

void RotationNode::OnGyro(const std::string& id, const gyro_sample_t& m,
                          const std::string& channel) {
    if (!std::isfinite(m.gyro_v) || !std::isfinite(m.temp_c)) {
        // Skipped: the hole it leaves is a sequence gap, so a move around it is rejected.
        status_.Reject("non-finite", channel + ": gyro_v and temp_c must be finite (seq " +
                                         std::to_string(m.seq) + ")");
        return;
    }
    auto it = sensors_.find(id);
    if (it == sensors_.end()) {
        it = sensors_.emplace(id, std::make_unique<Sensor>(options_.estimator)).first;
        status_.SetExtra("sensors", static_cast<double>(sensors_.size()));
    }
    Sensor& sensor = *it->second;
    if (!sensor.time.InOrder(m.utime, channel, status_)) return;
    sensor.time.Advance(m.utime);
    sensor.estimator.AddSample(motion::GyroSampleOf(m));
    PollAndPublish(id, sensor);
}

void RotationNode::OnEncoder(const motion::EncoderReading& reading) {
    for (auto& [id, sensor] : sensors_) sensor->estimator.AddEncoder(reading);  // slip check
    if (auto move = detector_.Feed(reading)) {
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
    } else if (m.event == "setpoint" || m.event == "rotation" || m.event == "restart") {
        // An estimator started (or restarted) mid-run learns the run from the next event.
        if (run_id_.empty()) run_id_ = m.run_id;
    } else {
        status_.Reject("unknown event",
                       "RUN_EVENT: event '" + m.event +
                           "' is not start, setpoint, rotation, restart, stop or abort");
    }
}

void RotationNode::PollAndPublish(const std::string& id, Sensor& sensor) {
    for (const rotation::Point& p : sensor.estimator.Poll(View())) {
        bus_.Publish(channels::Sensitivity(id), ToMessage(id, run_id_, p));
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

}  // namespace gyrocal::rotation::node
