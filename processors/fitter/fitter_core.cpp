#include "fitter_core.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "model/convert.hpp"

namespace gyrocal::fitter {

namespace {

std::string Fmt(double v, int prec = 4) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    return buf;
}

bool SameModel(const gyrocal::model_t& a, const gyrocal::model_t& b) {
    return a.term_names == b.term_names && a.coeffs == b.coeffs && a.method == b.method &&
           a.t0_c == b.t0_c;
}

bool SameSet(const gyrocal::coeff_set_t& a, const gyrocal::coeff_set_t& b) {
    return a.coeff_set_id == b.coeff_set_id && a.run_id == b.run_id &&
           a.plateau_ids == b.plateau_ids && a.rotation_ids == b.rotation_ids &&
           SameModel(a.offset, b.offset) && SameModel(a.sensitivity, b.sensitivity);
}

std::string Describe(const fit::FitResult& r) {
    std::string s = r.model.method;
    if (r.model.method == "wls")
        s += " d" + std::to_string(static_cast<int>(r.model.term_names.size()) - 1);
    s += " (" + std::to_string(r.model.n_points) + " pts";
    if (r.dof > 0) s += ", chi2/dof " + Fmt(r.chi2_per_dof, 3);
    if (std::isfinite(r.overdispersion))
        s += ", overdispersion c " + Fmt(r.overdispersion, 3) + " on " +
             std::to_string(r.overdispersion_dof) + " dof";
    s += ")";
    if (r.scatter_exceeds_errors) s += " SCATTER EXCEEDS STATED ERRORS";
    return s;
}

}  // namespace

std::string CoreOptions::Problem() const {
    if (const std::string p = fit.Problem(); !p.empty()) return p;
    if (!std::isfinite(nominal_sensitivity_v_per_dps) || !(nominal_sensitivity_v_per_dps > 0.0))
        return "--nominal-sensitivity-v-per-dps must be a finite number > 0";
    if (!std::isfinite(plateau_slow_noise_dps) || plateau_slow_noise_dps < 0.0 ||
        plateau_slow_noise_dps > 10.0)
        return "--plateau-slow-noise-dps must be in [0, 10] deg/s";
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
    } else if (e.event == "stop") {
        if (!run_id_.empty() && e.run_id != run_id_) {
            out.rejections.push_back({"wrong_run", "RUN_EVENT stop for run '" + e.run_id +
                                                       "' while run '" + run_id_ + "' is current"});
            return out;
        }
        for (auto& [id, s] : sensors_) Refit(id, s, /*force=*/true, out);
    }
    return out;
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
                                                 p.sensor_id + ": gyro_sem_v " + Fmt(p.gyro_sem_v) +
                                                 " must be > 0"});
        return out;
    }
    SensorState& s = sensors_[p.sensor_id];
    if (s.plateaus.count(p.plateau_id)) ++duplicates_;  // a replay: the newer copy replaces it
    s.plateaus[p.plateau_id] = p;
    Refit(p.sensor_id, s, false, out);
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
    Refit(r.sensor_id, s, false, out);
    return out;
}

void FitterCore::Refit(const std::string& sensor_id, SensorState& s, bool force, CoreOutput& out) {
    s.summary.n_plateaus = s.plateaus.size();
    s.summary.n_rotations = s.rotations.size();
    if (s.plateaus.empty()) {
        s.summary.text = "no plateaus yet";
        if (force)
            out.rejections.push_back(
                {"fit_refused", sensor_id + ": run stopped with rotations but no plateau"});
        return;
    }
    std::vector<fit::FitPoint> opts;
    int64_t newest_utime = 0;
    for (const auto& [id, p] : s.plateaus) {
        fit::FitPoint pt;
        pt.inputs.temp_c = p.temp_mean_c;
        pt.inputs.supply_v = p.supply_mean_v;
        pt.y = p.gyro_mean_v;
        pt.sigma_y = std::hypot(p.gyro_sem_v, options_.plateau_slow_noise_dps *
                                                  options_.nominal_sensitivity_v_per_dps);
        pt.id = id;
        opts.push_back(pt);
        newest_utime = std::max(newest_utime, p.utime);
    }
    const fit::FitResult offset =
        fit::FitPolynomial(opts, model::kOffsetQuantity, Pooled(sensor_id, true));
    s.offset_ref_chi2 = offset.ok() ? offset.reference_chi2 : 0.0;
    s.offset_ref_dof = offset.ok() ? offset.reference_dof : 0;
    if (!offset.ok()) {
        const std::string why =
            std::string("offset refused: ") + fit::ToString(offset.refusal) + ": " + offset.detail;
        s.summary.fitted = false;
        s.summary.text = why;
        // Too few temperatures is the normal state early in a run; anything else (or still too few
        // when the run stops) is a refusal worth counting, once per change of reason.
        const bool expected = offset.refusal == fit::Refusal::kTooFewTemperatures && !force;
        if (!expected && (why != s.last_refusal || force))
            out.rejections.push_back({"fit_refused", sensor_id + " " + why});
        s.last_refusal = why;
        return;
    }

    model::CoeffSet set;
    set.sensor_id = sensor_id;
    set.run_id = run_id_;
    set.source = options_.source;
    set.offset = offset.model;
    set.plateau_ids = offset.used_ids;
    std::string sens_text;
    if (s.rotations.empty()) {
        model::Model& m = set.sensitivity;
        m.quantity = model::kSensitivityQuantity;
        m.term_names = {"1"};
        m.coeffs = Eigen::VectorXd::Constant(1, options_.nominal_sensitivity_v_per_dps);
        m.covariance = Eigen::MatrixXd::Constant(1, 1, model::kUnknown);  // not measured
        m.t0_c = offset.model.t0_c;
        m.temp_min_c = offset.model.temp_min_c;
        m.temp_max_c = offset.model.temp_max_c;
        m.n_points = 0;
        m.method = "nominal";
        sens_text = "sensitivity NOMINAL " + Fmt(options_.nominal_sensitivity_v_per_dps) +
                    " V/dps (no rotations)";
    } else {
        std::vector<fit::FitPoint> spts;
        for (const auto& [id, r] : s.rotations) {
            fit::FitPoint pt;
            pt.inputs.temp_c = r.temp_c;
            pt.inputs.direction = r.direction;
            pt.y = r.sensitivity_v_per_dps;
            pt.sigma_y = r.sensitivity_stderr_v_per_dps;
            pt.id = id;
            spts.push_back(pt);
            newest_utime = std::max(newest_utime, r.utime);
        }
        fit::FitResult sens =
            fit::FitPolynomial(spts, model::kSensitivityQuantity, Pooled(sensor_id, false));
        s.sens_ref_chi2 = sens.ok() ? sens.reference_chi2 : 0.0;
        s.sens_ref_dof = sens.ok() ? sens.reference_dof : 0;
        if (sens.ok()) {
            sens_text = "sensitivity " + Describe(sens);
        } else {
            const std::string why = std::string(fit::ToString(sens.refusal)) + ": " + sens.detail;
            sens = fit::FitWeightedMean(spts, model::kSensitivityQuantity);
            if (!sens.ok()) {
                out.rejections.push_back(
                    {"fit_refused", sensor_id + " sensitivity refused: " + sens.detail});
                s.summary.text = "sensitivity refused: " + sens.detail;
                return;
            }
            sens_text = "sensitivity MEAN of " + std::to_string(spts.size()) +
                        " rotations (temperature fit " + why + ")";
        }
        set.sensitivity = sens.model;
        set.rotation_ids = sens.used_ids;
    }
    set.utime = newest_utime;
    set.coeff_set_id = newest_utime;

    gyrocal::coeff_set_t msg;
    try {
        msg = model::ToMsg(set);
        (void)model::FromMsg(msg);  // the exact check every consumer will apply
    } catch (const model::ModelError& e) {
        out.rejections.push_back(
            {"model_mismatch", sensor_id + ": coefficient set not published: " + e.what()});
        return;
    }
    s.last_refusal.clear();
    s.summary.fitted = true;
    s.summary.offset_chi2_per_dof = offset.chi2_per_dof;
    s.summary.offset_overdispersion = offset.overdispersion;
    s.summary.text = "offset " + Describe(offset) + ", " + sens_text;
    if (force || !s.last || !SameSet(*s.last, msg)) {
        s.last = msg;
        out.publish.push_back(msg);
        ++published_;
    }
}

fit::FitOptions FitterCore::Pooled(const std::string& sensor_id, bool offset) const {
    fit::FitOptions o = options_.fit;
    for (const auto& [id, other] : sensors_) {
        if (id == sensor_id) continue;
        o.pooled_chi2 += offset ? other.offset_ref_chi2 : other.sens_ref_chi2;
        o.pooled_dof += offset ? other.offset_ref_dof : other.sens_ref_dof;
    }
    return o;
}

std::map<std::string, SensorSummary> FitterCore::Summaries() const {
    std::map<std::string, SensorSummary> m;
    for (const auto& [id, s] : sensors_) m[id] = s.summary;
    return m;
}

}  // namespace gyrocal::fitter
