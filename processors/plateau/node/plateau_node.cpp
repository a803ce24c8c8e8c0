#include "processors/plateau/node/plateau_node.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gyrocal/plateau_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/motion/node/motion_options.hpp"
#include "processors/plateau/node/noise_message.hpp"
#include "processors/plateau/node/plateau_message.hpp"

namespace gyrocal::plateau::node {

namespace {

constexpr const char* kProcess = "gyrocal-plateau";

bool Finite(double v) { return std::isfinite(v); }
}  // namespace

std::string PlateauOptions::Validate() const {
    if (std::string e = motion::node::ValidateInput(sensors, encoder_id); !e.empty()) return e;
    if (std::string e = detector.Validate(); !e.empty()) return motion::node::AsOption(e);
    if (std::string e = move.Validate(); !e.empty()) return motion::node::AsOption(e);
    if (!(motion_guard_s >= 0 && motion_guard_s <= 60))
        return "--motion-guard-s must be in [0, 60] s";
    if (!(encoder_stale_s > 0 && encoder_stale_s <= 600))
        return "--encoder-stale-s must be in (0, 600] s";
    if (std::string e = noise.Validate(); !e.empty()) return e;
    if (!(noise_period_s >= 1 && noise_period_s <= 86400))
        return "--noise-period-s must be in [1, 86400] s";
    return "";
}

PlateauNode::PlateauNode(const PlateauOptions& options)
    : MotionNode(kProcess, options.lcm_url, options.sensors, options.encoder_id),
      options_(options),
      motion_(options.move, options.motion_guard_s, options.encoder_stale_s),
      chamber_setpoint_c_(std::numeric_limits<double>::quiet_NaN()) {
    bus_.Subscribe<chamber_state_t>(
        std::string(channels::kChamberState),
        motion::node::Guarded(
            status_, [this](const chamber_state_t& m, const std::string&) { OnChamberState(m); }));
}

PlateauNode::Sensor& PlateauNode::SensorFor(const std::string& id) {
    auto it = sensors_.find(id);
    if (it != sensors_.end()) return *it->second;
    auto sensor = std::make_unique<Sensor>(options_.detector, options_.noise);
    if (!run_id_.empty()) sensor->detector.StartRun(run_id_);
    sensor->detector.SetChamberSetpoint(chamber_setpoint_c_);
    Sensor& ref = *sensor;
    sensors_.emplace(id, std::move(sensor));
    status_.SetExtra("sensors", static_cast<double>(sensors_.size()));
    return ref;
}

void PlateauNode::OnGyro(const std::string& id, const gyro_sample_t& m,
                         const std::string& channel) {
    if (!Finite(m.temp_c) || !Finite(m.gyro_v) || !Finite(m.temp_v)) {
        status_.Reject("non-finite", channel + ": temp_c, gyro_v and temp_v must be finite (seq " +
                                         std::to_string(m.seq) + ")");
        return;
    }
    Sensor& sensor = SensorFor(id);
    if (!sensor.time.InOrder(m.utime, channel, status_)) return;
    sensor.time.Advance(m.utime);
    sensor.pending.push_back(plateau::SampleOf(m));
    Drain(id, sensor);
}

void PlateauNode::OnEncoder(const motion::EncoderReading& reading) {
    motion_.Feed(reading);
    DrainAll();
}

void PlateauNode::OnChamberState(const chamber_state_t& m) {
    if (!chamber_time_.InOrder(m.utime, "CHAMBER_STATE", status_)) return;
    if (std::isinf(m.setpoint_c)) {
        status_.Reject("non-finite", "CHAMBER_STATE: setpoint_c is infinite");
        return;
    }
    chamber_time_.Advance(m.utime);
    chamber_setpoint_c_ = m.setpoint_c;
    for (auto& [id, sensor] : sensors_) sensor->detector.SetChamberSetpoint(m.setpoint_c);
}

void PlateauNode::OnRunEvent(const run_event_t& m) {
    // A detector started (or restarted by its supervisor) in the middle of a run learns the run
    // from the next event that names it; "restart" (another process came back) changes nothing
    // else: re-arming would throw away windows being averaged.
    if (run_id_.empty() && m.event != "stop" && m.event != "abort" && !m.run_id.empty()) {
        run_id_ = m.run_id;
        for (auto& [id, sensor] : sensors_) sensor->detector.AdoptRun(run_id_);
    }
    if (m.event == "restart") return;
    if (m.event == "start") {
        if (m.run_id != run_id_)
            for (auto& [id, sensor] : sensors_) sensor->noise.Reset();  // a new run's own noise
        run_id_ = m.run_id;
        for (auto& [id, sensor] : sensors_) sensor->detector.StartRun(run_id_);
    } else if (m.event == "stop" || m.event == "abort") {
        for (auto& [id, sensor] : sensors_) PublishNoise(id, *sensor);  // the run's final estimate
        run_id_.clear();
        for (auto& [id, sensor] : sensors_) sensor->detector.EndRun();
    } else if (m.event == "setpoint") {
        if (std::isinf(m.setpoint_c)) {
            status_.Reject("non-finite", "RUN_EVENT setpoint: setpoint_c is infinite");
            return;
        }
        for (auto& [id, sensor] : sensors_) sensor->detector.OnSetpointEvent(m.setpoint_c);
        if (std::isfinite(m.setpoint_c)) chamber_setpoint_c_ = m.setpoint_c;
    } else if (m.event != "rotation") {
        status_.Reject("unknown event",
                       "RUN_EVENT: event '" + m.event +
                           "' is not start, setpoint, rotation, restart, stop or abort");
    }
}

void PlateauNode::Drain(const std::string& id, Sensor& sensor) {
    while (!sensor.pending.empty() &&
           motion_.Decided(sensor.pending.front().utime, sensor.time.newest_utime())) {
        plateau::Sample s = sensor.pending.front();
        sensor.pending.pop_front();
        s.moving = motion_.Moving(s.utime);
        sensor.noise.Add(s, s.moving);
        const plateau::Step step = sensor.detector.Feed(s);
        if (step.plateau || s.utime - sensor.last_noise_utime >= options_.noise_period_s * 1e6)
            PublishNoise(id, sensor);
        Publish(id, step);
    }
}

void PlateauNode::DrainAll() {
    int64_t oldest = std::numeric_limits<int64_t>::max();
    for (auto& [id, sensor] : sensors_) {
        Drain(id, *sensor);
        oldest = std::min(oldest, sensor->pending.empty() ? sensor->time.newest_utime()
                                                          : sensor->pending.front().utime);
    }
    if (!sensors_.empty()) motion_.Prune(oldest);
}

void PlateauNode::PublishNoise(const std::string& id, Sensor& sensor) {
    if (sensor.noise.newest_utime() == 0) return;  // no sample yet
    sensor.last_noise_utime = sensor.noise.newest_utime();
    bus_.Publish(channels::Noise(id), ToNoiseMessage(id, run_id_, sensor.noise.Estimate()));
}

void PlateauNode::Publish(const std::string& id, const plateau::Step& step) {
    if (step.refused) {
        ++refused_;
        status_.SetExtra("windows_refused", static_cast<double>(refused_));
        status_.Reject("window refused", channels::Gyro(id) + ": " + *step.refused);
    }
    if (step.plateau) {
        bus_.Publish(channels::Plateau(id), ToMessage(id, *step.plateau));
        ++plateaus_;
        status_.SetExtra("plateaus", static_cast<double>(plateaus_));
    }
    if (step.state) {
        const plateau::StateReport& r = *step.state;
        // For a progress display reading STATUS: state 0 waiting .. 3 done, and the fraction.
        status_.SetExtra(id + ".state", static_cast<double>(static_cast<int>(r.state)));
        status_.SetExtra(id + ".averaging_progress", r.averaging_progress);
        plateau_state_t msg;
        msg.utime = r.utime;
        msg.sensor_id = id;
        msg.state = plateau::StateName(r.state);
        msg.temp_c = r.temp_c;
        msg.temp_slope_c_per_min = r.temp_slope_c_per_min;
        msg.temp_std_c = r.temp_std_c;
        msg.stable_for_s = r.stable_for_s;
        msg.averaging_progress = r.averaging_progress;
        msg.last_plateau_id = r.last_plateau_id;
        bus_.Publish(channels::Stability(id), msg);
    }
}

}  // namespace gyrocal::plateau::node
