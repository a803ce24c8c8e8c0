#include "processors/sequencer/ramp_procedure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lcmtypes/text/join.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::sequencer {
namespace {

constexpr double kFirstTurnS = 30.0;  // [s] at rest at the start temperature before the first pair

int64_t Us(double s) { return static_cast<int64_t>(std::llround(s * 1e6)); }

}  // namespace

std::unique_ptr<Runner> MakeRunner(ProcedureOptions options) {
    if (options.profile.continuous) return std::make_unique<RampProcedure>(std::move(options));
    return std::make_unique<Procedure>(std::move(options));
}

RampProcedure::RampProcedure(ProcedureOptions options) : options_(std::move(options)) {
    options_.Validate();
    if (!options_.profile.continuous)
        throw std::invalid_argument("profile " + options_.profile.name +
                                    ": the ramp procedure needs a continuous profile");
}

std::vector<Order> RampProcedure::OnTime(int64_t utime) {
    if (phase_ == Phase::kDone) return {};
    now_utime_ = std::max(now_utime_, utime);
    if (phase_ == Phase::kIdle) {
        std::vector<Order> out{RunEventOrder{"start", "profile " + options_.profile.name, -1, NAN}};
        auto more = EnterLeg(0, utime);
        out.insert(out.end(), more.begin(), more.end());
        next_turn_utime_ = utime + Us(kFirstTurnS);
        start_utime_ = utime;
        return out;
    }
    std::vector<Order> out;
    if (finishing_.empty()) {
        if (reached_utime_ < 0 &&
            static_cast<double>(now_utime_ - leg_start_utime_) * 1e-6 > options_.plateau_timeout_s)
            return Finish("abort", "chamber fault: the air did not reach " +
                                       text::Sig(Waypoint(leg_), 3) + " degC within " +
                                       text::Sig(options_.plateau_timeout_s, 3) + " s");
        if (reached_utime_ >= 0 &&
            static_cast<double>(now_utime_ - reached_utime_) * 1e-6 >= options_.dwell_s) {
            if (leg_ + 1 < static_cast<int>(options_.profile.setpoints_c.size()))
                out = EnterLeg(leg_ + 1, now_utime_);
            else
                finishing_ = "completed";
        }
    }
    if (phase_ == Phase::kWaitRotation &&
        static_cast<double>(now_utime_ - move_start_utime_) * 1e-6 > options_.rotation_timeout_s) {
        notes_.push_back(
            "move " + text::Sig(options_.moves_deg[static_cast<size_t>(move_index_)], 3) +
            " deg at " + text::Sig(air_c_, 3) + " degC air: no sensitivity point within " +
            text::Sig(options_.rotation_timeout_s, 3) + " s from " + text::Join(pending_, ","));
        pending_.clear();
        auto more = MoveDone(now_utime_);
        out.insert(out.end(), more.begin(), more.end());
    }
    if (phase_ == Phase::kRamping && !finishing_.empty()) {
        auto more = Finish("stop", finishing_);
        out.insert(out.end(), more.begin(), more.end());
    } else if (phase_ == Phase::kRamping && now_utime_ >= next_turn_utime_) {
        next_turn_utime_ = now_utime_ + Us(options_.turn_interval_s);
        auto more = EnterMove(0, now_utime_);
        out.insert(out.end(), more.begin(), more.end());
    }
    return out;
}

std::vector<Order> RampProcedure::OnChamber(int64_t utime, double air_c) {
    if (phase_ == Phase::kDone) return {};
    if (std::isfinite(air_c)) air_c_ = air_c;
    if (leg_ >= 0 && reached_utime_ < 0 && std::isfinite(air_c) &&
        std::abs(air_c - Waypoint(leg_)) <= options_.reach_band_c)
        reached_utime_ = std::max(utime, leg_start_utime_);
    return OnTime(utime);
}

std::vector<Order> RampProcedure::OnSensitivity(const std::string& sensor_id, int64_t utime,
                                                bool accepted, const std::string& reject_reason) {
    if (phase_ != Phase::kWaitRotation || utime < move_start_utime_) return OnTime(utime);
    if (!pending_.erase(sensor_id)) return OnTime(utime);
    if (!accepted)
        notes_.push_back("move " +
                         text::Sig(options_.moves_deg[static_cast<size_t>(move_index_)], 3) +
                         " deg, " + sensor_id + ": rejected: " + reject_reason);
    if (!pending_.empty()) return OnTime(utime);
    auto out = MoveDone(std::max(utime, now_utime_));
    auto more = OnTime(utime);
    out.insert(out.end(), more.begin(), more.end());
    return out;
}

std::vector<Order> RampProcedure::OnCoefficients(const std::string& sensor_id, int64_t utime,
                                                 const CoeffUncertainty& u) {
    if (phase_ == Phase::kDone) return {};
    uncertainty_[sensor_id] = u;
    if (finishing_.empty() && TargetsMet()) {
        now_utime_ = std::max(now_utime_, utime);
        saved_s_ = RemainingPlanS();
        const double elapsed_s = static_cast<double>(now_utime_ - start_utime_) * 1e-6;
        std::string what;
        if (options_.target_offset_dps > 0)
            what += "offset <= " + text::Sig(options_.target_offset_dps, 3) + " deg/s";
        if (options_.target_sensitivity_pct > 0)
            what += std::string(what.empty() ? "" : ", ") +
                    "sensitivity <= " + text::Sig(options_.target_sensitivity_pct, 3) + " %";
        finishing_ = "completed early: target reached (" + what + ") for " +
                     std::to_string(uncertainty_.size()) + " units at " +
                     text::Sig(elapsed_s / 3600.0, 3) + " h; chamber time saved " +
                     text::Sig(saved_s_ / 3600.0, 3) + " h of the planned " +
                     text::Sig((elapsed_s + saved_s_) / 3600.0, 3) + " h";
    }
    return OnTime(utime);
}

bool RampProcedure::TargetsMet() const {
    const bool by_offset = options_.target_offset_dps > 0;
    const bool by_sens = options_.target_sensitivity_pct > 0;
    if (!by_offset && !by_sens) return false;
    if (leg_ < 1) return false;  // one direction only so far: rate and branch terms not separable
    for (const std::string& id : options_.sensor_ids) {
        const auto it = uncertainty_.find(id);
        if (it == uncertainty_.end()) return false;
        const CoeffUncertainty& u = it->second;
        if (by_offset && !(u.offset_dps <= options_.target_offset_dps)) return false;
        if (by_sens && !(u.sensitivity_pct <= options_.target_sensitivity_pct)) return false;
    }
    return true;
}

double RampProcedure::RemainingPlanS() const {
    if (phase_ == Phase::kDone || leg_ < 0) return 0.0;
    const double rate_c_per_s = options_.ramp_rate_c_per_min / 60.0;
    double s = 0.0;
    if (reached_utime_ < 0) {
        const double from_c = std::isfinite(air_c_) ? air_c_ : Waypoint(leg_);
        s += std::abs(Waypoint(leg_) - from_c) / rate_c_per_s + options_.dwell_s;
    } else {
        s += std::max(0.0,
                      options_.dwell_s - static_cast<double>(now_utime_ - reached_utime_) * 1e-6);
    }
    for (int i = leg_ + 1; i < static_cast<int>(options_.profile.setpoints_c.size()); ++i)
        s += std::abs(Waypoint(i) - Waypoint(i - 1)) / rate_c_per_s + options_.dwell_s;
    return s;
}

std::vector<Order> RampProcedure::EnterLeg(int index, int64_t utime) {
    leg_ = index;
    leg_start_utime_ = utime;
    reached_utime_ = -1;
    if (phase_ == Phase::kIdle) phase_ = Phase::kRamping;
    const double wp = Waypoint(index);
    return {RunEventOrder{"setpoint",
                          "ramp leg " + std::to_string(index + 1) + " of " +
                              std::to_string(options_.profile.setpoints_c.size()) + " to " +
                              text::Sig(wp, 3) + " degC",
                          index, wp},
            ChamberOrder{wp, options_.ramp_rate_c_per_min}};
}

std::vector<Order> RampProcedure::EnterMove(int index, int64_t utime) {
    move_index_ = index;
    move_start_utime_ = utime;
    phase_ = Phase::kWaitRotation;
    pending_ = std::set<std::string>(options_.sensor_ids.begin(), options_.sensor_ids.end());
    const double move = options_.moves_deg[static_cast<size_t>(index)];
    return {RunEventOrder{"rotation",
                          "move " + text::Sig(move, 3) + " deg on the ramp (pair " +
                              std::to_string(turns_done_ + 1) + ")",
                          leg_, Waypoint(leg_)},
            TurntableOrder{move, options_.rotation_rate_dps, options_.rotation_accel_dps2}};
}

std::vector<Order> RampProcedure::MoveDone(int64_t utime) {
    if (move_index_ + 1 < static_cast<int>(options_.moves_deg.size()))
        return EnterMove(move_index_ + 1, utime);
    ++turns_done_;
    move_index_ = -1;
    phase_ = Phase::kRamping;
    return {};
}

std::vector<Order> RampProcedure::Finish(const std::string& event, const std::string& reason) {
    phase_ = Phase::kDone;
    outcome_ = event == "stop" ? "completed" : "abort";
    std::string why = reason;
    if (event == "stop" && !notes_.empty())
        why += "; " + std::to_string(notes_.size()) + " turn(s) without every point";
    outcome_reason_ = why;
    pending_.clear();
    return {RunEventOrder{event, why, leg_, leg_ >= 0 ? Waypoint(leg_) : NAN}};
}

}  // namespace gyrocal::sequencer
