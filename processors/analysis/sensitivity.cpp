#include "processors/analysis/sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "processors/fit/fit.hpp"
#include "processors/fit/levels.hpp"

namespace gyrocal::analysis {

fit::FitPoint SensitivityFitPoint(const SensitivityInput& s) {
    fit::FitPoint p;
    p.inputs.temp_c = s.temp_c;
    p.inputs.direction = s.direction;
    p.y = s.sensitivity_v_per_dps;
    p.sigma_y = s.stderr_v_per_dps;
    p.id = s.rotation_id;
    return p;
}

namespace {

std::vector<fit::FitPoint> ToPoints(const std::vector<SensitivityInput>& in) {
    std::vector<fit::FitPoint> pts;
    for (const SensitivityInput& s : in) {
        if (!s.accepted || !std::isfinite(s.temp_c) || !std::isfinite(s.sensitivity_v_per_dps) ||
            !(s.stderr_v_per_dps > 0.0) || (s.direction != 1 && s.direction != -1))
            continue;
        pts.push_back(SensitivityFitPoint(s));
    }
    return pts;
}

double RelRms(const fit::FitResult& f, const std::vector<fit::FitPoint>& pts) {
    double ss = 0.0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const double r = f.residuals[static_cast<Eigen::Index>(i)] / pts[i].y;
        ss += r * r;
    }
    return std::sqrt(ss / static_cast<double>(pts.size()));
}

// Leave one temperature level out: chi^2 of the held-out points under the declared (terms) and
// the extended (ext_terms) model, each fitted on the other levels.
struct LevelCv {
    double sse_base = 0.0, sse_ext = 0.0;
    int folds = 0;  // levels whose two fits succeeded
};
LevelCv LeaveOneLevelOut(const std::vector<fit::FitPoint>& pts,
                         const std::vector<fit::Level>& levels,
                         const std::vector<std::string>& terms,
                         const std::vector<std::string>& ext_terms, double t0) {
    LevelCv cv;
    for (const fit::Level& l : levels) {
        std::vector<fit::FitPoint> train, test;
        for (size_t i = 0; i < pts.size(); ++i)
            (std::find(l.members.begin(), l.members.end(), i) != l.members.end() ? test : train)
                .push_back(pts[i]);
        const fit::FitResult fb = fit::FitWls(train, terms, t0, model::kSensitivityQuantity);
        const fit::FitResult fe = fit::FitWls(train, ext_terms, t0, model::kSensitivityQuantity);
        if (!fb.ok() || !fe.ok()) continue;
        const model::Evaluator eb(fb.model), ee(fe.model);
        for (const auto& p : test) {
            const double rb =
                (p.y - eb.Value(p.inputs, model::RangePolicy::kExtrapolate)) / p.sigma_y;
            const double re =
                (p.y - ee.Value(p.inputs, model::RangePolicy::kExtrapolate)) / p.sigma_y;
            cv.sse_base += rb * rb;
            cv.sse_ext += re * re;
        }
        ++cv.folds;
    }
    return cv;
}

// The sf_asymmetry candidate: the direction term added to the declared terms, judged by its z^2
// and the leave-one-level-out gain; out.extended and out.added when both pass.
void TestDirectionTerm(const std::vector<fit::FitPoint>& pts, const std::vector<fit::Level>& levels,
                       const std::vector<std::string>& terms, double t0, const AnalysisOptions& o,
                       SensitivityOutcome& out) {
    int n_pos = 0, n_neg = 0;
    for (const auto& p : pts) (p.inputs.direction > 0 ? n_pos : n_neg)++;
    if (n_pos < 2 || n_neg < 2) {
        out.candidate.note = "not tested: needs >= 2 rotations in each direction (have " +
                             std::to_string(n_pos) + " positive, " + std::to_string(n_neg) +
                             " negative)";
        return;
    }
    std::vector<std::string> ext_terms = terms;
    ext_terms.push_back("direction");
    const fit::FitResult ext = fit::FitWls(pts, ext_terms, t0, model::kSensitivityQuantity);
    if (!ext.ok() || ext.dof < 1) {
        out.candidate.note = "not tested: too few points for the direction term (" +
                             (ext.ok() ? std::string("no degree of freedom left") : ext.detail) +
                             ")";
        return;
    }
    const auto last = static_cast<Eigen::Index>(ext_terms.size() - 1);
    const double inflate = std::max(1.0, ext.chi2_per_dof);
    const double c = ext.model.coeffs[last];
    const double var = ext.model.covariance(last, last) * inflate;
    out.candidate.z2 = c * c / var;
    out.candidate.step = 1;
    const LevelCv cv = LeaveOneLevelOut(pts, levels, terms, ext_terms, t0);
    if (cv.folds == 0 || !(cv.sse_base > 0.0)) {
        out.candidate.note = "not tested: no cross-validation fold could be fitted";
        out.candidate.decision = Decision::kNotTested;
        return;
    }
    out.candidate.cv_gain = (cv.sse_base - cv.sse_ext) / cv.sse_base;
    const bool pass = out.candidate.z2 > o.min_z2 && out.candidate.cv_gain > o.min_cv_gain;
    out.candidate.decision = pass ? Decision::kAdded : Decision::kRejected;
    if (!pass) return;
    out.extended = ext.model;
    out.extended->method = "analysis";
    out.rel_rms_after = RelRms(ext, pts);
    out.chi2_dof_after = ext.chi2_per_dof;
    AddedEffect a;
    a.effect = "sf_asymmetry";
    a.term = "direction";
    a.unit = "V/(deg/s)";
    a.coefficient = c;
    a.stderr_ = std::sqrt(var);
    out.added = a;
}

}  // namespace

SensitivityOutcome AnalyzeSensitivity(const std::vector<SensitivityInput>& in,
                                      const AnalysisOptions& o) {
    SensitivityOutcome out;
    out.candidate.effect = "sf_asymmetry";
    out.candidate.term = "direction";
    const std::vector<fit::FitPoint> pts = ToPoints(in);
    out.n_points = static_cast<int>(pts.size());
    if (pts.empty()) {
        out.problem = "no accepted rotation (sensitivity) points";
        out.candidate.note = "not tested: no rotations in the run";
        return out;
    }
    std::vector<double> temps;
    for (const auto& p : pts) temps.push_back(p.inputs.temp_c);
    const std::vector<fit::Level> levels = fit::TemperatureLevels(temps, o.same_level_tolerance_c);
    const size_t degree_cap = levels.size() - 1;
    std::vector<std::string> terms = o.sensitivity_terms;
    if (terms.size() > degree_cap + 1) terms.resize(degree_cap + 1);
    const double t0 = 5.0 * std::round(0.5 * (levels.front().temp_c + levels.back().temp_c) / 5.0);
    const fit::FitResult base = fit::FitWls(pts, terms, t0, model::kSensitivityQuantity);
    if (!base.ok()) {
        out.problem = "declared sensitivity model could not be fitted: " + base.detail;
        out.candidate.note = "not tested: " + out.problem;
        return out;
    }
    out.declared = base.model;
    out.extended = base.model;
    out.rel_rms_before = out.rel_rms_after = RelRms(base, pts);
    out.chi2_dof_before = out.chi2_dof_after = base.chi2_per_dof;
    TestDirectionTerm(pts, levels, terms, t0, o, out);
    return out;
}

}  // namespace gyrocal::analysis
