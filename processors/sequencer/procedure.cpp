#include "processors/sequencer/procedure.hpp"

#include <cmath>
#include <stdexcept>

#include "lcmtypes/text/join.hpp"
#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::sequencer {
namespace {

std::string Join(const std::map<std::string, std::string>& why) {
    std::string out;
    for (const auto& [id, reason] : why) out += (out.empty() ? "" : "; ") + id + ": " + reason;
    return out;
}

constexpr text::NameTable<Phase, 6> kPhaseNames{
    {{Phase::kIdle, "idle"},
     {Phase::kWaitPlateau, "waiting for plateaus"},
     {Phase::kWaitRotation, "rotating"},
     {Phase::kWaitRetry, "at rest before turning again"},
     {Phase::kRamping, "ramping"},
     {Phase::kDone, "done"}}};

}  // namespace

std::optional<Profile> NamedProfile(const std::string& name) {
    // ADXRS610/613 are specified over -40..+105 °C; the chamber range here is -40..85.
    if (name == "six") return Profile{"six", {25.0, -40.0, -10.0, 45.0, 65.0, 85.0}};
    if (name == "five") return Profile{"five", {-40.0, -10.0, 25.0, 55.0, 85.0}};
    if (name == "seed3") return Profile{"seed3", {-10.0, 30.0, 60.0}};
    if (name == "ramp") return Profile{"ramp", {-40.0, 85.0}, true};
    return std::nullopt;
}

std::vector<std::string> ProfileNames() { return {"six", "five", "seed3", "ramp"}; }

std::string ProfilesHelp() {
    std::string out;
    for (const std::string& name : ProfileNames()) {
        std::string list;
        // Held by name: a range-for over a member of the temporary optional would read freed
        // memory (the temporary dies before the loop body runs).
        const std::optional<Profile> profile = NamedProfile(name);
        for (double t : profile->setpoints_c) list += (list.empty() ? "" : ",") + text::Sig(t);
        out += (out.empty() ? "" : ", ") + name + " (" + list + " C)";
    }
    return out;
}

namespace {

// Throws "<what> <value> <rule>" (e.g. "ramp rate 40 degC/min: valid is (0, 30]") unless `ok`.
void Require(bool ok, const std::string& what, double value, const std::string& rule) {
    if (!ok) throw std::invalid_argument(what + " " + text::Sig(value) + " " + rule);
}

}  // namespace

void ProcedureOptions::Validate() const {
    if (profile.setpoints_c.empty())
        throw std::invalid_argument("profile: at least one setpoint is needed");
    for (double t : profile.setpoints_c)
        Require(std::isfinite(t) && t >= -60.0 && t <= 150.0, "setpoint", t,
                "degC: valid is -60..150 degC");
    if (sensor_ids.empty())
        throw std::invalid_argument("sensors: at least one sensor id is needed");
    Require(ramp_rate_c_per_min > 0.0 && ramp_rate_c_per_min <= 30.0, "ramp rate",
            ramp_rate_c_per_min, "degC/min: valid is (0, 30]");
    Require(plateau_timeout_s > 0.0, "plateau timeout", plateau_timeout_s, "s: must be > 0");
    Require(rotation_timeout_s > 0.0, "rotation timeout", rotation_timeout_s, "s: must be > 0");
    for (double m : moves_deg)
        Require(std::isfinite(m) && m != 0.0 && std::abs(m) <= 360.0, "move", m,
                "deg: valid is [-360, 360] without 0");
    Require(rotation_rate_dps > 0.0 && rotation_rate_dps <= 300.0, "rotation rate",
            rotation_rate_dps, "deg/s: valid is (0, 300]");
    Require(rotation_accel_dps2 > 0.0, "rotation acceleration", rotation_accel_dps2,
            "deg/s^2: must be > 0");
    Require(retry_wait_s >= 0.0 && retry_wait_s <= 600.0, "retry wait", retry_wait_s,
            "s: valid is 0..600");
    if (move_attempts < 1 || move_attempts > 5)
        throw std::invalid_argument("move attempts " + std::to_string(move_attempts) +
                                    ": valid is 1..5");
    Require(turn_interval_s >= 10.0 && turn_interval_s <= 7200.0, "turn interval", turn_interval_s,
            "s: valid is 10..7200");
    Require(dwell_s >= 0.0 && dwell_s <= 7200.0, "dwell", dwell_s, "s: valid is 0..7200");
    Require(reach_band_c > 0.0 && reach_band_c <= 20.0, "reach band", reach_band_c,
            "degC: valid is (0, 20]");
    Require(target_offset_dps >= 0.0 && std::isfinite(target_offset_dps), "target offset",
            target_offset_dps, "deg/s: valid is >= 0 (0 = no target)");
    Require(target_sensitivity_pct >= 0.0 && target_sensitivity_pct <= 100.0, "target sensitivity",
            target_sensitivity_pct, "%: valid is 0..100 (0 = no target)");
    if (profile.continuous && resume_setpoint_index >= 0)
        throw std::invalid_argument(
            "resume setpoint index: a continuous (ramp) run cannot be resumed");
    if (resume_setpoint_index < -1 ||
        resume_setpoint_index >= static_cast<int>(profile.setpoints_c.size()))
        throw std::invalid_argument("resume setpoint index " +
                                    std::to_string(resume_setpoint_index) + ": valid is 0.." +
                                    std::to_string(profile.setpoints_c.size() - 1) +
                                    " (0-based, of the profile's setpoints) or -1 for a new run");
}

const char* PhaseName(Phase p) { return text::NameOf(kPhaseNames, p); }

Procedure::Procedure(ProcedureOptions options) : options_(std::move(options)) {
    options_.Validate();
}

std::vector<Order> Procedure::OnTime(int64_t utime) {
    if (phase_ == Phase::kDone) return {};
    now_utime_ = std::max(now_utime_, utime);
    if (phase_ == Phase::kIdle) {
        if (options_.resume_setpoint_index >= 0)
            return EnterSetpoint(options_.resume_setpoint_index, utime);
        std::vector<Order> out{RunEventOrder{"start", "profile " + options_.profile.name, -1, NAN}};
        auto more = EnterSetpoint(0, utime);
        out.insert(out.end(), more.begin(), more.end());
        return out;
    }
    const double waited_s = static_cast<double>(now_utime_ - phase_start_utime_) * 1e-6;
    if (phase_ == Phase::kWaitPlateau && waited_s > options_.plateau_timeout_s) {
        return Finish("abort", "chamber fault: no plateau within " +
                                   text::Sig(options_.plateau_timeout_s) + " s at setpoint " +
                                   text::Sig(options_.profile.setpoints_c[setpoint_index_]) +
                                   " degC for sensors " + text::Join(pending_, ","));
    }
    if (phase_ == Phase::kWaitRetry && waited_s >= options_.retry_wait_s)
        return EnterMove(move_index_, now_utime_, retry_why_);
    if (phase_ == Phase::kWaitRotation && waited_s > options_.rotation_timeout_s) {
        for (const auto& id : pending_)
            move_failed_[id] =
                "no sensitivity point within " + text::Sig(options_.rotation_timeout_s) + " s";
        pending_.clear();
        return MoveDone(now_utime_);
    }
    return {};
}

std::vector<Order> Procedure::OnPlateau(const std::string& sensor_id, int64_t utime,
                                        double setpoint_c) {
    // Guard: only plateaus that end after the current setpoint was ordered, at that setpoint.
    if (phase_ != Phase::kWaitPlateau || utime < phase_start_utime_) return {};
    const double current_c = options_.profile.setpoints_c[static_cast<size_t>(setpoint_index_)];
    if (std::isfinite(setpoint_c) && std::abs(setpoint_c - current_c) > 0.01) return {};
    pending_.erase(sensor_id);
    if (!pending_.empty()) return {};
    move_index_ = -1;
    return Advance(utime);
}

std::vector<Order> Procedure::OnSensitivity(const std::string& sensor_id, int64_t utime,
                                            bool accepted, const std::string& reject_reason) {
    if (phase_ != Phase::kWaitRotation || utime < phase_start_utime_) return {};
    if (!pending_.erase(sensor_id)) return {};  // not awaited, or already answered this attempt
    if (!accepted) move_failed_[sensor_id] = "rejected: " + reject_reason;
    if (!pending_.empty()) return {};
    return MoveDone(utime);
}

std::vector<Order> Procedure::MoveDone(int64_t utime) {
    if (move_failed_.empty()) return Advance(utime);
    const std::string what =
        "move " + text::Sig(options_.moves_deg[static_cast<size_t>(move_index_)]) +
        " deg at setpoint " +
        text::Sig(options_.profile.setpoints_c[static_cast<size_t>(setpoint_index_)]) + " degC";
    if (move_attempt_ < options_.move_attempts) {
        retry_why_ = "attempt " + std::to_string(move_attempt_ + 1) + " of " +
                     std::to_string(options_.move_attempts) + " after " + Join(move_failed_);
        phase_ = Phase::kWaitRetry;
        phase_start_utime_ = std::max(utime, now_utime_);  // the rest counts from the data now
        return OnTime(phase_start_utime_);                 // at once when retry_wait_s is 0
    }
    notes_.push_back(
        what + ": no accepted sensitivity point after " + std::to_string(move_attempt_) +
        (move_attempt_ == 1 ? " attempt" : " attempts") + " (" + Join(move_failed_) + ")");
    return Advance(utime);
}

void Runner::EndedElsewhere(const std::string& event, const std::string& reason) {
    if (phase_ == Phase::kDone) return;
    phase_ = Phase::kDone;
    outcome_ = event == "stop" ? "completed" : "abort";
    outcome_reason_ = reason;
    pending_.clear();
}

std::vector<Order> Runner::Abort(const std::string& reason) {
    if (phase_ == Phase::kDone) return {};
    return Finish("abort", reason);
}

std::vector<Order> Procedure::EnterSetpoint(int index, int64_t utime) {
    setpoint_index_ = index;
    move_index_ = -1;
    phase_ = Phase::kWaitPlateau;
    phase_start_utime_ = utime;
    pending_ = std::set<std::string>(options_.sensor_ids.begin(), options_.sensor_ids.end());
    const double sp = options_.profile.setpoints_c[static_cast<size_t>(index)];
    return {RunEventOrder{"setpoint",
                          "setpoint " + std::to_string(index + 1) + " of " +
                              std::to_string(options_.profile.setpoints_c.size()),
                          index, sp},
            ChamberOrder{sp, options_.ramp_rate_c_per_min}};
}

std::vector<Order> Procedure::EnterMove(int index, int64_t utime, const std::string& why) {
    move_attempt_ = index == move_index_ && !why.empty() ? move_attempt_ + 1 : 1;
    move_failed_.clear();
    move_index_ = index;
    phase_ = Phase::kWaitRotation;
    phase_start_utime_ = utime;
    pending_ = std::set<std::string>(options_.sensor_ids.begin(), options_.sensor_ids.end());
    const double move = options_.moves_deg[static_cast<size_t>(index)];
    return {
        RunEventOrder{
            "rotation", "move " + text::Sig(move) + " deg" + (why.empty() ? "" : " (" + why + ")"),
            setpoint_index_, options_.profile.setpoints_c[static_cast<size_t>(setpoint_index_)]},
        TurntableOrder{move, options_.rotation_rate_dps, options_.rotation_accel_dps2}};
}

std::vector<Order> Procedure::Advance(int64_t utime) {
    const int next_move = move_index_ + 1;
    if (next_move < static_cast<int>(options_.moves_deg.size())) return EnterMove(next_move, utime);
    const int next_sp = setpoint_index_ + 1;
    if (next_sp < static_cast<int>(options_.profile.setpoints_c.size()))
        return EnterSetpoint(next_sp, utime);
    if (notes_.empty()) return Finish("stop", "completed");
    std::string missing;
    for (const auto& n : notes_) missing += (missing.empty() ? "" : "; ") + n;
    return Finish("stop", "completed; missing: " + missing);
}

std::vector<Order> Procedure::Finish(const std::string& event, const std::string& reason) {
    phase_ = Phase::kDone;
    outcome_ = event == "stop" ? "completed" : "abort";
    outcome_reason_ = reason;
    pending_.clear();
    return {RunEventOrder{event, reason, setpoint_index_,
                          setpoint_index_ >= 0
                              ? options_.profile.setpoints_c[static_cast<size_t>(setpoint_index_)]
                              : NAN}};
}

}  // namespace gyrocal::sequencer
