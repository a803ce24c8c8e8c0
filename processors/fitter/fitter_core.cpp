#include "processors/fitter/fitter_core.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/pooling.hpp"

namespace gyrocal::fitter {

namespace {}  // namespace

std::string CoreOptions::Validate() const {
    if (const std::string p = fit.Validate(); !p.empty()) return p;
    if (const std::string p = outliers.Validate(); !p.empty()) return p;
    if (!(pool_alpha > 0.0 && pool_alpha < 0.5)) return "--pool-alpha must be in (0, 0.5)";
    if (!(repeat_tolerance_c >= 0.0 && repeat_tolerance_c <= 20.0))
        return "--repeat-tolerance-c must be in [0, 20] degC";
    if (!std::isfinite(nominal_sensitivity_v_per_dps) || !(nominal_sensitivity_v_per_dps > 0.0))
        return "--nominal-sensitivity-v-per-dps must be a finite number > 0";
    if (!std::isfinite(plateau_slow_noise_dps) || plateau_slow_noise_dps > 10.0)
        return "--plateau-slow-noise-dps must be in [0, 10] deg/s, or < 0 for the run's own "
               "Allan deviation";
    return "";
}

FitterCore::FitterCore(CoreOptions options) : options_(std::move(options)) {}

CoreOutput FitterCore::OnRunEvent(const gyrocal::run_event_t& e) {
    CoreOutput out;
    if (e.event == "start") {
        // A repeated start of the current run (a late joiner's resend, a replayed log) must not
        // throw away the points already collected.
        if (e.run_id == run_id_ && !e.run_id.empty()) return out;
        run_id_ = e.run_id;
        run_sensors_.clear();
        for (const std::string& id : e.sensor_ids) run_sensors_.insert(id);
        sensors_.clear();
        final_utime_.reset();
    } else if (e.event == "stop") {
        if (!run_id_.empty() && e.run_id != run_id_) {
            out.rejections.push_back({"wrong_run", "RUN_EVENT stop for run '" + e.run_id +
                                                       "' while run '" + run_id_ + "' is current"});
            return out;
        }
        final_utime_ = e.utime;
        RefitFinal(e.utime, out);
    }
    return out;
}

void FitterCore::RefitFinal(int64_t final_utime, CoreOutput& out) {
    // First pass: every unit's evidence from its final points; second: the final sets.
    CoreOutput settle;
    for (auto& [id, s] : sensors_) RefitSensor(id, s, Refit{false, true, final_utime}, settle);
    for (auto& [id, s] : sensors_) RefitSensor(id, s, Refit{true, true, final_utime}, out);
}

void FitterCore::RefitAfterPoint(const std::string& sensor_id, SensorState& s, CoreOutput& out) {
    if (!final_utime_) return RefitSensor(sensor_id, s, Refit{true, false, 0}, out);
    // After the stop every set is final: a late point remakes them, distinct from the last ones.
    *final_utime_ += 1;
    RefitFinal(*final_utime_, out);
}

bool FitterCore::Admit(const std::string& kind, const std::string& msg_sensor,
                       const std::string& channel_sensor, const std::string& msg_run,
                       CoreOutput& out) {
    if (msg_sensor != channel_sensor) {
        out.rejections.push_back({"wrong_sensor", kind + " on channel of sensor '" +
                                                      channel_sensor + "' carries sensor_id '" +
                                                      msg_sensor + "'"});
        return false;
    }
    if (!run_sensors_.empty() && !run_sensors_.count(msg_sensor)) {
        out.rejections.push_back(
            {"unknown_sensor",
             kind + " for sensor '" + msg_sensor + "', which is not among the run's sensor_ids"});
        return false;
    }
    if (!run_id_.empty() && msg_run != run_id_) {
        out.rejections.push_back({"wrong_run", kind + " of sensor '" + msg_sensor +
                                                   "' belongs to run '" + msg_run +
                                                   "', current run is '" + run_id_ + "'"});
        return false;
    }
    if (run_id_.empty() && !msg_run.empty()) run_id_ = msg_run;  // started after the run's start
    return true;
}

CoreOutput FitterCore::OnPlateau(const gyrocal::plateau_t& p, const std::string& channel_sensor) {
    CoreOutput out;
    if (!Admit("plateau " + std::to_string(p.plateau_id), p.sensor_id, channel_sensor, p.run_id,
               out))
        return out;
    if (!std::isfinite(p.temp_mean_c) || !std::isfinite(p.gyro_mean_v) ||
        !std::isfinite(p.gyro_sem_v)) {
        out.rejections.push_back(
            {"non_finite", "plateau " + std::to_string(p.plateau_id) + " of " + p.sensor_id +
                               ": temp_mean_c, gyro_mean_v and gyro_sem_v must be finite"});
        return out;
    }
    if (!(p.gyro_sem_v > 0.0)) {
        out.rejections.push_back({"bad_sem", "plateau " + std::to_string(p.plateau_id) + " of " +
                                                 p.sensor_id + ": gyro_sem_v " +
                                                 text::Sig(p.gyro_sem_v, 4) + " must be > 0"});
        return out;
    }
    SensorState& s = sensors_[p.sensor_id];
    if (s.plateaus.count(p.plateau_id)) ++duplicates_;  // a replay: the newer copy replaces it
    s.plateaus[p.plateau_id] = p;
    RefitAfterPoint(p.sensor_id, s, out);
    return out;
}

CoreOutput FitterCore::OnSensitivity(const gyrocal::sensitivity_point_t& r,
                                     const std::string& channel_sensor) {
    CoreOutput out;
    if (!Admit("sensitivity point " + std::to_string(r.rotation_id), r.sensor_id, channel_sensor,
               r.run_id, out))
        return out;
    if (!r.accepted) {  // the rotation estimator already said why; not bad input
        ++not_accepted_;
        return out;
    }
    if (!std::isfinite(r.temp_c) || !std::isfinite(r.sensitivity_v_per_dps) ||
        !std::isfinite(r.sensitivity_stderr_v_per_dps)) {
        out.rejections.push_back(
            {"non_finite", "sensitivity point " + std::to_string(r.rotation_id) + " of " +
                               r.sensor_id +
                               ": temp_c, sensitivity_v_per_dps and its stderr must be finite"});
        return out;
    }
    if (!(r.sensitivity_stderr_v_per_dps > 0.0)) {
        out.rejections.push_back({"bad_sem", "sensitivity point " + std::to_string(r.rotation_id) +
                                                 " of " + r.sensor_id +
                                                 ": sensitivity_stderr_v_per_dps must be > 0"});
        return out;
    }
    SensorState& s = sensors_[r.sensor_id];
    if (s.rotations.count(r.rotation_id)) ++duplicates_;
    s.rotations[r.rotation_id] = r;
    RefitAfterPoint(r.sensor_id, s, out);
    return out;
}

CoreOutput FitterCore::OnNoise(const gyrocal::noise_t& n, const std::string& channel_sensor) {
    CoreOutput out;
    if (!Admit("noise estimate", n.sensor_id, channel_sensor, n.run_id, out)) return out;
    const double values[] = {n.bias_instability_v, n.still_s};
    for (double v : values)
        if (std::isinf(v) || (std::isfinite(v) && v < 0)) {
            out.rejections.push_back({"bad_noise", "NOISE_" + n.sensor_id +
                                                       ": bias_instability_v and still_s must be "
                                                       ">= 0 (NaN = no fit)"});
            return out;
        }
    // Kept until the next plateau's refit picks it (fitter_core.hpp: the newest not later than
    // the newest plateau); older ones are no longer needed once a newer one precedes a plateau.
    sensors_[n.sensor_id].noise[n.utime] = n;
    return out;
}

fit::FitOptions FitterCore::Pooled(const std::string& sensor_id, bool offset,
                                   std::string& note) const {
    // The pool among the OTHER units (fit/pooling.hpp).
    std::vector<fit::UnitEvidence> units;
    for (const auto& [id, s] : sensors_) {
        if (id == sensor_id) continue;
        const Evidence& e = offset ? s.offset_evidence : s.sens_evidence;
        units.push_back({id, e.chi2, e.dof});
    }
    const fit::Pool pool = fit::Pool::Decide(units, options_.pool_alpha);
    fit::PooledEvidence e;
    for (const fit::UnitEvidence& u : units) {
        if (pool.left_out().count(u.id) || u.dof <= 0) continue;
        e.chi2 += u.chi2;
        e.dof += u.dof;
    }
    fit::FitOptions o = options_.fit;
    o.pooled_chi2 = e.chi2;
    o.pooled_dof = e.dof;
    note.clear();
    for (const auto& [id, why] : pool.left_out())
        note += (note.empty() ? "" : "; ") + std::string("unit ") + id + " left out of the pool";
    return o;
}

std::map<std::string, SensorSummary> FitterCore::Summaries() const {
    std::map<std::string, SensorSummary> m;
    for (const auto& [id, s] : sensors_)
        if (!s.plateaus.empty() || !s.rotations.empty()) m[id] = s.summary;
    return m;
}

}  // namespace gyrocal::fitter
