// FitterCore::RefitSensor: a unit's points -> its coefficient set and fit report.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/pooling.hpp"
#include "processors/fit/repeatability.hpp"
#include "processors/fitter/fitter_core.hpp"
#include "processors/fitter/slow_noise.hpp"
#include "processors/model/convert.hpp"

namespace gyrocal::fitter {

namespace {

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
    if (r.dof > 0) s += ", chi2/dof " + text::Sig(r.chi2_per_dof, 3);
    if (std::isfinite(r.overdispersion))
        s += ", overdispersion c " + text::Sig(r.overdispersion, 3) + " on " +
             std::to_string(r.overdispersion_dof) + " dof";
    s += ")";
    if (r.scatter_exceeds_errors) s += " SCATTER EXCEEDS STATED ERRORS";
    return s;
}

// The part of a fit a report and a summary show: model, outliers, pooling.
struct Part {
    model::Model model;
    bool complete = false;
    std::string reason;  // why partial
    std::string detail;  // for the report
    std::string text;    // for the summary
    std::vector<fit::Exclusion> excluded;
    std::vector<int64_t> ids;
};

Part FromCalibration(const fit::CalibrationFit& c, const std::string& what,
                     const std::string& pool_note) {
    Part p;
    p.model = c.fit.model;
    p.complete = c.complete;
    p.reason = c.complete ? "" : what + ": " + c.partial_reason;
    p.detail = c.fit.detail + "; outliers: " + c.outlier_check +
               (pool_note.empty() ? "" : "; pooling: " + pool_note);
    p.text = what + " " + Describe(c.fit) + (c.complete ? "" : " PARTIAL");
    p.excluded = c.excluded;
    p.ids = c.fit.used_ids;
    return p;
}

Part Nominal(double s, const model::Model& offset) {
    Part p;
    model::Model& m = p.model;
    m.quantity = model::kSensitivityQuantity;
    m.term_names = {"1"};
    m.coeffs = Eigen::VectorXd::Constant(1, s);
    m.covariance = Eigen::MatrixXd::Constant(1, 1, model::kUnknown);  // not measured
    m.t0_c = offset.t0_c;
    m.temp_min_c = offset.temp_min_c;
    m.temp_max_c = offset.temp_max_c;
    m.n_points = 0;
    m.method = "nominal";
    p.reason = "sensitivity: nominal " + text::Sig(s, 4) + " V/(deg/s), no accepted rotation";
    p.detail = "nominal (no accepted rotation)";
    p.text = "sensitivity NOMINAL " + text::Sig(s, 4) + " V/dps (no rotations)";
    return p;
}

void AddExclusions(gyrocal::fit_report_t& r, const std::vector<fit::Exclusion>& xs,
                   const std::string& kind) {
    for (const fit::Exclusion& x : xs) {
        gyrocal::fit_exclusion_t e;
        e.kind = kind;
        e.item_id = x.id;
        e.temp_c = x.temp_c;
        e.value = x.value;
        e.residual = x.residual;
        e.residual_sigma = x.residual_sigma;
        e.statistic = x.statistic;
        e.threshold = x.threshold;
        e.reason = x.reason;
        r.excluded.push_back(e);
    }
    r.num_excluded = static_cast<int32_t>(r.excluded.size());
}

void AddRepeats(gyrocal::fit_report_t& r, const std::vector<fit::Repeat>& reps) {
    for (const fit::Repeat& x : reps) {
        gyrocal::repeatability_t e;
        e.temp_c = x.temp_c;
        e.first_plateau_id = x.first_id;
        e.second_plateau_id = x.second_id;
        e.first_temp_c = x.first_temp_c;
        e.second_temp_c = x.second_temp_c;
        e.first_approach = static_cast<int8_t>(x.first_approach);
        e.second_approach = static_cast<int8_t>(x.second_approach);
        e.offset_diff_v = x.diff_v;
        e.offset_diff_stderr_v = x.diff_sigma_v;
        e.offset_diff_dps = x.diff_dps;
        e.offset_diff_stderr_dps = x.diff_sigma_dps;
        e.z = x.z;
        e.verdict = x.verdict;
        r.repeats.push_back(e);
    }
    r.num_repeats = static_cast<int32_t>(r.repeats.size());
}

gyrocal::fit_report_t NoSetReport(const std::string& id, const std::string& run, int64_t utime,
                                  const std::string& source, const std::string& reason) {
    gyrocal::fit_report_t r{};
    r.utime = utime;
    r.sensor_id = id;
    r.run_id = run;
    r.coeff_set_id = -1;
    r.source = source;
    r.is_final = true;
    r.status = "none";
    r.reason = reason;
    r.slow_noise_v = model::kUnknown;
    r.slow_noise_dps = model::kUnknown;
    return r;
}

struct OffsetPoints {
    std::vector<fit::FitPoint> points;
    int64_t newest_utime = 0;
};

OffsetPoints PlateauPoints(const std::map<int64_t, gyrocal::plateau_t>& plateaus, double slow_v) {
    OffsetPoints o;
    for (const auto& [pid, p] : plateaus) {
        fit::FitPoint pt;
        pt.inputs.temp_c = p.temp_mean_c;
        pt.inputs.supply_v = p.supply_mean_v;
        pt.y = p.gyro_mean_v;
        pt.sigma_y = std::hypot(p.gyro_sem_v, slow_v);
        pt.id = pid;
        o.points.push_back(pt);
        o.newest_utime = std::max(o.newest_utime, p.utime);
    }
    return o;
}

// The sensitivity part: nominal without rotations, else FitCalibration of the rotations.
}  // namespace

std::vector<fit::FitPoint> RotationPoints(
    const std::map<int64_t, gyrocal::sensitivity_point_t>& rotations) {
    std::vector<fit::FitPoint> spts;
    for (const auto& [rid, r] : rotations) {
        fit::FitPoint pt;
        pt.inputs.temp_c = r.temp_c;
        pt.inputs.direction = r.direction;
        pt.y = r.sensitivity_v_per_dps;
        pt.sigma_y = r.sensitivity_stderr_v_per_dps;
        pt.id = rid;
        spts.push_back(pt);
    }
    return spts;
}

namespace {

// The sensitivity part: nominal without rotations, else the rotations' fit.
Part SensitivityPart(const std::map<int64_t, gyrocal::sensitivity_point_t>& rotations,
                     const fit::CalibrationFit& c, const std::string& pool_note, double nominal,
                     const model::Model& offset, int64_t& newest_utime) {
    if (rotations.empty()) return Nominal(nominal, offset);
    for (const auto& [rid, r] : rotations) newest_utime = std::max(newest_utime, r.utime);
    if (c.fit.ok()) return FromCalibration(c, "sensitivity", pool_note);
    Part p = Nominal(nominal, offset);
    p.reason = "sensitivity: rotations unusable (" + c.fit.detail + "): nominal";
    return p;
}

gyrocal::fit_report_t MakeReport(const model::CoeffSet& set, bool final, const Part& off,
                                 const Part& sens, const SlowNoise& slow,
                                 const std::vector<fit::Repeat>& repeats) {
    gyrocal::fit_report_t r{};
    model::CopySetKey(r, set);
    r.is_final = final;
    r.status = off.complete && sens.complete ? "complete" : "partial";
    r.reason = off.reason + (!off.reason.empty() && !sens.reason.empty() ? "; " : "") + sens.reason;
    r.offset_detail = off.detail;
    r.sensitivity_detail = sens.detail;
    r.slow_noise_v = slow.v;
    model::ModelInputs at;
    at.temp_c = set.sensitivity.t0_c;
    r.slow_noise_dps =
        slow.v / std::abs(model::Evaluate(set.sensitivity, at, model::RangePolicy::kClip).value);
    r.slow_noise_source = slow.source;
    AddExclusions(r, off.excluded, "plateau");
    AddExclusions(r, sens.excluded, "rotation");
    AddRepeats(r, repeats);
    return r;
}

void Summarize(SensorSummary& sum, const fit::FitResult& offset, const Part& off, const Part& sens,
               const gyrocal::fit_report_t& report) {
    sum.fitted = true;
    sum.complete = report.status == "complete";
    sum.excluded = static_cast<size_t>(report.num_excluded);
    sum.offset_chi2_per_dof = offset.chi2_per_dof;
    sum.offset_overdispersion = offset.overdispersion;
    sum.slow_noise_dps = report.slow_noise_dps;
    sum.text = off.text + ", " + sens.text +
               (sum.excluded ? ", " + std::to_string(sum.excluded) + " point(s) excluded" : "");
}

}  // namespace

void FitterCore::RefitSensor(const std::string& id, SensorState& s, const Refit& how,
                             CoreOutput& out) {
    s.summary.n_plateaus = s.plateaus.size();
    s.summary.n_rotations = s.rotations.size();
    if (s.plateaus.empty()) {
        s.summary.text = "no plateaus yet";
        if (how.final && how.emit) {
            const std::string why = "run stopped with rotations but no plateau: no offset";
            out.rejections.push_back({"fit_refused", id + ": " + why});
            out.reports.push_back(NoSetReport(id, run_id_, how.stop_utime, options_.source, why));
        }
        return;
    }
    const SlowNoise slow =
        ChooseSlowNoise(options_.plateau_slow_noise_dps, options_.nominal_sensitivity_v_per_dps,
                        s.noise, s.plateaus, id);
    OffsetPoints pts = PlateauPoints(s.plateaus, slow.v);
    std::string pool_note;
    const fit::CalibrationFit offset =
        FitPooled(id, pts.points, true, s.offset_evidence, pool_note);
    if (!offset.fit.ok() || (!offset.complete && !how.final)) {
        NotYet(id, s, offset, how, out);
        return;
    }
    const Part off = FromCalibration(offset, "offset", pool_note);
    std::string sens_note;
    fit::CalibrationFit sens_fit;
    if (!s.rotations.empty())
        sens_fit = FitPooled(id, RotationPoints(s.rotations), false, s.sens_evidence, sens_note);
    const Part sens =
        SensitivityPart(s.rotations, sens_fit, sens_note, options_.nominal_sensitivity_v_per_dps,
                        off.model, pts.newest_utime);

    model::CoeffSet set;
    set.sensor_id = id;
    set.run_id = run_id_;
    set.source = options_.source;
    set.offset = off.model;
    set.plateau_ids = off.ids;
    set.sensitivity = sens.model;
    set.rotation_ids = sens.ids;
    // The final set is made by the stop event (fitter_core.hpp).
    set.utime = how.final ? std::max(how.stop_utime, pts.newest_utime + 1) : pts.newest_utime;
    set.coeff_set_id = set.utime;
    gyrocal::coeff_set_t msg;
    try {
        msg = model::ToMsg(set);
        (void)model::FromMsg(msg);  // the exact check every consumer will apply
    } catch (const model::ModelError& e) {
        out.rejections.push_back(
            {"model_mismatch", id + ": coefficient set not published: " + e.what()});
        return;
    }
    const gyrocal::fit_report_t report = MakeReport(
        set, how.final, off, sens, slow,
        fit::Repeatability(pts.points, set.offset, set.sensitivity, options_.repeat_tolerance_c));
    s.last_refusal.clear();
    Summarize(s.summary, offset.fit, off, sens, report);
    if (!how.emit) return;
    if (how.final && report.status != "complete")
        out.rejections.push_back({"fit_partial", id + ": " + report.reason});
    if (how.final || !s.last || !SameSet(*s.last, msg)) {
        s.last = msg;
        out.publish.push_back(msg);
        out.reports.push_back(report);
        ++published_;
    }
}

fit::CalibrationFit FitterCore::FitPooled(const std::string& id,
                                          const std::vector<fit::FitPoint>& points, bool offset,
                                          Evidence& evidence, std::string& note) const {
    const std::string quantity = offset ? model::kOffsetQuantity : model::kSensitivityQuantity;
    const fit::FitOptions pooled = Pooled(id, offset, note);
    fit::CalibrationFit c = fit::FitCalibration(points, quantity, pooled, options_.outliers);
    if (!c.fit.ok()) {
        evidence = {};
        return c;
    }
    const std::string disagrees =
        fit::Disagreement({id, c.fit.reference_chi2, c.fit.reference_dof},
                          {pooled.pooled_chi2, pooled.pooled_dof}, options_.pool_alpha);
    if (!disagrees.empty()) {
        // Its scatter is not the others': its own evidence only; what the test left out stays out.
        fit::CalibrationFit own =
            fit::FitCalibration(c.kept, quantity, options_.fit, options_.outliers);
        own.excluded.insert(own.excluded.begin(), c.excluded.begin(), c.excluded.end());
        c = std::move(own);
        note = "this unit's " + disagrees + (note.empty() ? "" : "; " + note);
    }
    evidence = {c.fit.ok() ? c.fit.reference_chi2 : 0.0, c.fit.ok() ? c.fit.reference_dof : 0};
    return c;
}

void FitterCore::NotYet(const std::string& id, SensorState& s, const fit::CalibrationFit& offset,
                        const Refit& how, CoreOutput& out) {
    // Too few temperatures is the normal state early in a run; anything else is worth a STATUS
    // line, once per change of reason.
    const std::string why = offset.fit.ok()
                                ? "offset partial: " + offset.partial_reason
                                : std::string("offset refused: ") +
                                      fit::ToString(offset.fit.refusal) + ": " + offset.fit.detail;
    s.summary.fitted = false;
    s.summary.complete = false;
    s.summary.text = why;
    const bool expected = why.find("too_few_temperatures") != std::string::npos && !how.final;
    if (!expected && why != s.last_refusal && how.emit)
        out.rejections.push_back({"fit_refused", id + " " + why});
    if (how.final && how.emit)
        out.reports.push_back(NoSetReport(id, run_id_, how.stop_utime, options_.source, why));
    s.last_refusal = why;
}

}  // namespace gyrocal::fitter
