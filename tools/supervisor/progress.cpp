#include "tools/supervisor/progress.hpp"

#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::supervisor {

void Progress::OnRunEvent(const run_event_t& e) {
    run_id_ = e.run_id;
    last_event_ = e.event;
    if (e.event == "setpoint") {
        setpoint_index_ = e.setpoint_index;
        setpoint_c_ = e.setpoint_c;
        moves_done_at_setpoint_ = 0;
    } else if (e.event == "rotation") {
        // The event announces a move: the previous ones at this setpoint are done.
        ++moves_done_at_setpoint_;
    }
}

void Progress::OnChamber(const chamber_state_t& s) {
    have_chamber_ = true;
    air_c_ = s.air_c;
    if (first_utime_ < 0) first_utime_ = s.utime;
    last_utime_ = std::max(last_utime_, s.utime);
}

void Progress::OnStability(const plateau_state_t& s) { stability_[s.sensor_id] = s; }

void Progress::OnSensitivity(const sensitivity_point_t& s) {
    // Once per point: a restarted fitter's recovery publishes the run's points again.
    if (!points_seen_.insert({s.sensor_id, s.rotation_id}).second) return;
    (s.accepted ? rotations_accepted_ : rotations_rejected_) += 1;
}

void Progress::OnStatus(const status_t& s) {
    int64_t handler_errors = 0;  // an extra counter (bus.hpp): absent from older processes
    for (size_t i = 0; i < s.extra_names.size() && i < s.extra_values.size(); ++i)
        if (s.extra_names[i] == "handler_errors")
            handler_errors = static_cast<int64_t>(s.extra_values[i]);
    losses_by_process_[s.process + "@" + s.host + ":" + std::to_string(s.pid)] =
        s.seq_gaps + s.decode_errors + s.queue_drops + handler_errors;
}

void Progress::OnCoeffs(const coeff_set_t& c) { ++coeffs_by_sensor_[c.sensor_id]; }

int64_t Progress::drops() const {
    int64_t n = 0;
    for (const auto& [k, v] : losses_by_process_) n += v;
    return n;
}

double Progress::FractionDone() const {
    if (setpoints_total_ <= 0 || setpoint_index_ < 0) return 0.0;
    if (last_event_ == "stop") return 1.0;
    // Within a setpoint: waiting for the plateau is most of the time; count it as 3/4.
    double within = 0.0;
    if (moves_per_setpoint_ > 0 && moves_done_at_setpoint_ > 0)
        within = 0.75 + 0.25 * std::min(1.0, (moves_done_at_setpoint_ - 1.0) / moves_per_setpoint_);
    return std::clamp((setpoint_index_ + within) / setpoints_total_, 0.0, 1.0);
}

double Progress::EtaS(double wall_elapsed_s) const {
    const double f = FractionDone();
    if (f < 0.02) return -1.0;
    return wall_elapsed_s * (1.0 - f) / f;
}

std::string Progress::Line(double wall_elapsed_s) const {
    std::string line = setpoint_index_ >= 0
                           ? text::Printf("setpoint %d/%d (%.1f C)", setpoint_index_ + 1,
                                          setpoints_total_, setpoint_c_)
                           : "starting";
    if (have_chamber_) line += text::Printf(" | air %.1f C", air_c_);
    for (const auto& [id, s] : stability_) {
        if (s.state == "averaging")
            line += text::Printf(" | %s %.1f C averaging %.0f%%", id.c_str(), s.temp_c,
                                 100.0 * s.averaging_progress);
        else
            line += text::Printf(" | %s %.1f C %s %+.2f C/min", id.c_str(), s.temp_c,
                                 s.state.c_str(), s.temp_slope_c_per_min);
    }
    line += text::Printf(" | rotations %d ok %d rejected | losses %lld", rotations_accepted_,
                         rotations_rejected_, static_cast<long long>(drops()));
    if (first_utime_ >= 0) {
        const double sim_s = static_cast<double>(last_utime_ - first_utime_) * 1e-6;
        line += text::Printf(" | data %02d:%02d:%02d", static_cast<int>(sim_s) / 3600,
                             static_cast<int>(sim_s) / 60 % 60, static_cast<int>(sim_s) % 60);
    }
    const double eta = EtaS(wall_elapsed_s);
    if (eta >= 0) line += text::Printf(" | ~%.0f s left", eta);
    return line;
}

}  // namespace gyrocal::supervisor
