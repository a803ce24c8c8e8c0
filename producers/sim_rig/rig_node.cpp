#include "producers/sim_rig/rig_node.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::sim_rig {

namespace {
const char* kProcess = "gyrocal-sim-rig";
// A batch never runs more than this much simulated work before the bus is polled again, so
// commands are served even when publication cannot keep up with the pacing.
constexpr int64_t kMaxBatchGyroPeriods = 200;
// Wall time one pacing step may spend publishing before returning to RunLoop (heartbeat, stop).
constexpr std::chrono::milliseconds kBusyBudget(50);
// The units' power-on time is repeated this often (sim time) for late joiners.
constexpr int64_t kPowerRepeatUs = 10'000'000;
}  // namespace

SimRigNode::SimRigNode(const SimRigOptions& options)
    : options_(options),
      bus_(bus::BusOptions{options.lcm_url}),
      status_(bus_, kProcess),
      rig_(options.rig),
      batcher_(bus_, options.flow.batch_samples) {
    if (options_.speed <= 0.0)
        flow_ = std::make_unique<flow::FlowSource>(bus_, kProcess, options_.flow.Window());
    for (const auto& id : rig_.sensor_ids()) gyro_channels_.push_back(channels::Gyro(id));
    if (options_.duration_s > 0.0) {
        end_utime_ = options_.rig.start_utime +
                     static_cast<int64_t>(std::llround(options_.duration_s * 1e6));
    }
    if (options_.mode == "builtin") profile_.emplace(options_.profile);
    bus_.Subscribe<chamber_cmd_t>(
        std::string(channels::kChamberCmd),
        [this](const chamber_cmd_t& m, const std::string&) { OnChamberCmd(m); });
    bus_.Subscribe<turntable_cmd_t>(
        std::string(channels::kTurntableCmd),
        [this](const turntable_cmd_t& m, const std::string&) { OnTurntableCmd(m); });
    status_.SetExtra("units", static_cast<double>(rig_.sensor_ids().size()));
    status_.SetExtra("speed", options_.speed);
}

bool SimRigNode::IgnoredInBuiltinMode(const std::string& what, int64_t cmd_id) {
    if (!profile_) return false;
    status_.Reject(what + "_ignored", "--mode builtin runs its own profile; cmd_id " +
                                          std::to_string(cmd_id) + " ignored");
    return true;
}

void SimRigNode::OnChamberCmd(const chamber_cmd_t& cmd) {
    if (IgnoredInBuiltinMode("chamber_cmd", cmd.cmd_id)) return;
    const sim::CommandResult r =
        rig_.ChamberCommand(cmd.cmd_id, cmd.setpoint_c, cmd.ramp_rate_c_per_min);
    if (!r.accepted) status_.Reject("chamber_cmd_refused", "CHAMBER_CMD " + r.reason);
}

void SimRigNode::OnTurntableCmd(const turntable_cmd_t& cmd) {
    if (IgnoredInBuiltinMode("turntable_cmd", cmd.cmd_id)) return;
    const sim::CommandResult r =
        rig_.TurntableCommand(cmd.cmd_id, cmd.move_deg, cmd.rate_dps, cmd.accel_dps2);
    if (!r.accepted) status_.Reject("turntable_cmd_refused", "TURNTABLE_CMD " + r.reason);
}

void SimRigNode::PublishPower(int64_t utime) {
    batcher_.Flush();  // no channel overtakes another
    // Every unit of the rig is powered when the rig starts (its simulated power-on).
    for (const std::string& id : rig_.sensor_ids()) {
        power_state_t p;
        p.utime = utime;
        p.sensor_id = id;
        p.seq = power_seq_;
        p.power_on_utime = options_.rig.start_utime;
        p.source = "rig";
        bus_.Publish(channels::Power(id), p);
    }
    ++power_seq_;
    next_power_utime_ = utime + kPowerRepeatUs;
}

void SimRigNode::OnGyro(const sim::GyroReading& r, const sim::GyroTruth&) {
    if (r.unit_index == 0 && r.utime >= next_power_utime_) PublishPower(r.utime);
    gyro_sample_t m;
    m.utime = r.utime;
    m.sensor_id = *r.sensor_id;
    m.seq = r.seq;
    m.gyro_v = r.gyro_v;
    m.temp_v = r.temp_v;
    m.temp_c = r.temp_c;
    m.supply_v = r.supply_v;
    m.has_adc = r.has_adc;
    m.gyro_counts = r.gyro_counts;
    m.temp_counts = r.temp_counts;
    m.supply_counts = r.supply_counts;
    batcher_.Add(gyro_channels_[static_cast<size_t>(r.unit_index)], m);
}

void SimRigNode::OnEncoder(const sim::EncoderReading& r) {
    encoder_sample_t m;
    m.utime = r.utime;
    m.encoder_id = "TABLE";
    m.seq = r.seq;
    m.counts = r.counts;
    m.counts_per_rev = r.counts_per_rev;
    m.angle_deg = r.angle_deg;
    batcher_.AddEncoder(std::string(channels::kEncoder), m);
}

void SimRigNode::OnChamber(const sim::ChamberReading& r) {
    if (profile_) {
        if (profile_->done()) return;  // ended at the previous report; nothing more
        profile_->OnChamber(r, rig_);
        // Stop at this simulated instant, so a built-in run is the same whatever the pacing.
        if (profile_->done()) rig_.StopAfterCurrentEvent();
    }
    chamber_state_t m;
    m.utime = r.utime;
    m.seq = r.seq;
    m.cmd_id = r.cmd_id;
    m.setpoint_c = r.setpoint_c;
    m.air_c = r.air_c;
    m.at_setpoint = r.at_setpoint;
    m.fault = r.fault;
    batcher_.Flush();  // the samples before this state go first
    bus_.Publish(std::string(channels::kChamberState), m);
}

bool SimRigNode::Advance() {
    if (flow_) return AdvanceByConsumers();
    // Publish everything due up to the paced target. When behind, keep going for up to one
    // budget of wall time, serving queued commands between capped batches (Handle(0) never
    // blocks), instead of idling in RunLoop's poll while late.
    const auto call_start = std::chrono::steady_clock::now();
    if (OverMessageBudget()) return finished_;
    const int64_t cap_us =
        static_cast<int64_t>(kMaxBatchGyroPeriods * 1e6 / options_.rig.sample_rate_hz);
    int64_t target = 0;
    for (;;) {
        const double wall_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
        target = options_.rig.start_utime + static_cast<int64_t>(wall_s * options_.speed * 1e6);
        if (end_utime_ > 0) target = std::min(target, end_utime_);
        rig_.RunUntil(std::min(target, rig_.now_utime() + cap_us), *this);
        batcher_.Flush();
        if (rig_.next_event_utime() > target) break;  // caught up
        if (std::chrono::steady_clock::now() - call_start > kBusyBudget) break;
        if (OverMessageBudget()) break;
        bus_.Handle(std::chrono::milliseconds(0));
        if (profile_ && profile_->done()) break;
    }
    UpdateProgress(target);
    return finished_;
}

bool SimRigNode::AdvanceByConsumers() {
    // One batch period at a time (every unit's batch and the encoder's), as long as every
    // consumer has room (flow_window.hpp) and for at most one budget of wall time; commands are
    // served between steps. With nobody answering, only the message cap paces.
    const auto call_start = std::chrono::steady_clock::now();
    const int64_t step_us = static_cast<int64_t>(std::max(1, options_.flow.batch_samples) * 1e6 /
                                                 options_.rig.sample_rate_hz);
    for (;;) {
        flow_->Sync(rig_.now_utime());
        const std::optional<int64_t> credit = flow_->Credit();
        if (credit && *credit <= 0) {
            flow_->WaitForCredit(
                std::chrono::milliseconds(std::max<int64_t>(1, std::llround(options_.tick_ms))));
            break;
        }
        if (OverMessageBudget()) break;
        int64_t target = rig_.now_utime() + step_us;
        if (end_utime_ > 0) target = std::min(target, end_utime_);
        rig_.RunUntil(target, *this);
        batcher_.Flush();
        if (end_utime_ > 0 && rig_.next_event_utime() > end_utime_) break;
        if (profile_ && profile_->done()) break;
        if (std::chrono::steady_clock::now() - call_start > kBusyBudget) break;
        bus_.Handle(std::chrono::milliseconds(0));
    }
    flow_->Sync(rig_.now_utime());
    for (const auto& [name, value] : flow_->Extras()) status_.SetExtra(name, value);
    for (const std::string& line : flow_->TakeReports())
        std::cerr << kProcess << ": flow: " << line << "\n";
    UpdateProgress(rig_.now_utime());
    return finished_;
}

void SimRigNode::UpdateProgress(int64_t target) {
    const double lag_s = std::max<int64_t>(0, target - rig_.now_utime()) * 1e-6;
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    status_.SetExtra("sim_time_s", rig_.sim_seconds());
    status_.SetExtra("lag_s", lag_s);
    if (wall_s > 0) status_.SetExtra("speed_achieved", rig_.sim_seconds() / wall_s);
    if (end_utime_ > 0 && rig_.next_event_utime() > end_utime_) finished_ = true;
    if (profile_ && profile_->done()) finished_ = true;
}

bool SimRigNode::OverMessageBudget() const {
    if (options_.max_msgs_per_s <= 0.0) return false;
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    // One tick's worth of slack so the first batches are not throttled.
    const double allowed = (wall_s + 0.05) * options_.max_msgs_per_s;
    return static_cast<double>(bus_.counters().published) > allowed;
}

int SimRigNode::Run() {
    if (flow_) flow_->Discover();
    wall_start_ = std::chrono::steady_clock::now();
    status_.set_state(profile_ ? "builtin" : "commanded");
    const auto poll =
        std::chrono::milliseconds(std::max<int64_t>(1, std::llround(options_.tick_ms)));
    process::RunLoop(
        bus_, status_, [this] { return Advance(); }, poll);
    batcher_.Flush();
    // Finished on its own: every consumer has everything before the process goes.
    if (flow_ && finished_) flow_->Drain(rig_.now_utime());
    status_.set_state(finished_ ? "finished" : "stopped");
    status_.PublishNow();
    return 0;
}

}  // namespace gyrocal::sim_rig
