#include "processors/fit/calibration_fit.hpp"

#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/fit_util.hpp"
#include "processors/numeric/distributions.hpp"

namespace gyrocal::fit {

using namespace detail;

namespace {

bool CanFallBack(Refusal r) {
    return r == Refusal::kTooFewTemperatures || r == Refusal::kRangeTooNarrow ||
           r == Refusal::kIllConditioned;
}

// A line (two or more separated temperatures) or a weighted mean, after FitPolynomial refused.
FitResult LowerOrder(const std::vector<FitPoint>& pts, const std::string& quantity,
                     const FitOptions& o) {
    const std::vector<Level> levels = TemperatureLevels(Temps(pts), o.same_level_tolerance_c);
    const double t0 = o.t0_c ? *o.t0_c : DefaultT0(levels.front().temp_c, levels.back().temp_c);
    if (SeparatedLevelCount(levels, o.min_temp_separation_c) >= 2) {
        FitResult line =
            FitWls(pts, model::PolynomialTerms(1), t0, quantity, o.max_condition_number);
        if (line.ok()) {
            ApplyOverdispersion(line, line.chi2, line.dof, o);
            line.level_temps_c.clear();
            for (const Level& l : levels) line.level_temps_c.push_back(l.temp_c);
            line.detail = "degree 1 (a line: all the points allow)" + FitNotes(line) +
                          OverdispersionNotes(line);
            return line;
        }
    }
    FitResult mean = FitWeightedMean(pts, quantity);
    if (mean.ok()) {
        ApplyOverdispersion(mean, mean.chi2, mean.dof, o);
        mean.detail = "weighted mean (a constant: all the points allow)" + FitNotes(mean) +
                      OverdispersionNotes(mean);
    }
    return mean;
}

CalibrationFit FitOrFallBack(const std::vector<FitPoint>& pts, const std::string& quantity,
                             const FitOptions& o) {
    CalibrationFit out;
    out.kept = pts;
    out.fit = FitPolynomial(pts, quantity, o);
    if (out.fit.ok()) {
        out.complete = true;
        return out;
    }
    if (!CanFallBack(out.fit.refusal) || pts.empty()) return out;
    const std::string why = std::string(ToString(out.fit.refusal)) + ": " + out.fit.detail;
    FitResult lower = LowerOrder(pts, quantity, o);
    if (!lower.ok()) return out;
    out.fit = std::move(lower);
    out.partial_reason = "temperature model refused (" + why + "); published " + out.fit.detail;
    return out;
}

struct Screen {
    bool can_check = false;
    std::string why_not;
    size_t worst = 0;
    Exclusion worst_point;
    double worst_ratio = 0.0;  // |t| / threshold of the worst point
    size_t tested = 0;
};

// One pass of the leave-one-out test (see header): each point against the model fitted, with its
// order chosen on evidence, to the other points.
Screen ScreenOnce(const std::vector<FitPoint>& pts, const std::string& quantity,
                  const FitOptions& o, double alpha) {
    Screen s;
    const size_t n = pts.size();
    for (size_t i = 0; i < n; ++i) {
        std::vector<FitPoint> others;
        for (size_t k = 0; k < n; ++k)
            if (k != i) others.push_back(pts[k]);
        FitOptions loo = o;
        if (loo.method == Method::kThreePoint) loo.method = Method::kAuto;
        const FitResult f = FitPolynomial(others, quantity, loo);
        // The others must carry a model with a degree of freedom left to check the point against.
        if (!f.ok() || f.dof < 1) continue;
        const model::Evaluation e =
            model::Evaluate(f.model, pts[i].inputs, model::RangePolicy::kExtrapolate);
        const double sigma =
            std::sqrt(f.covariance_scale * pts[i].sigma_y * pts[i].sigma_y + e.variance);
        Exclusion x;
        x.id = pts[i].id;
        x.temp_c = pts[i].inputs.temp_c;
        x.value = pts[i].y;
        x.residual = pts[i].y - e.value;
        x.residual_sigma = sigma;
        x.statistic = x.residual / sigma;
        x.threshold =
            numeric::TwoSidedTQuantile(alpha / static_cast<double>(n), f.overdispersion_dof);
        ++s.tested;
        const double ratio = std::abs(x.statistic) / x.threshold;
        if (!s.can_check || ratio > s.worst_ratio) {
            s.worst = i;
            s.worst_point = x;
            s.worst_ratio = ratio;
        }
        s.can_check = true;
    }
    if (!s.can_check)
        s.why_not = "cannot check: " + std::to_string(n) +
                    " points; without any one of them the others leave no degree of freedom to "
                    "test it against";
    return s;
}

}  // namespace

std::string OutlierOptions::Validate() const {
    if (!(family_alpha > 0.0 && family_alpha < 0.5)) return "--outlier-alpha must be in (0, 0.5)";
    if (!(max_fraction >= 0.0 && max_fraction <= 0.5))
        return "outlier max fraction must be in [0, 0.5]";
    return "";
}

CalibrationFit FitCalibration(const std::vector<FitPoint>& points, const std::string& quantity,
                              const FitOptions& o, const OutlierOptions& oo) {
    std::vector<FitPoint> kept = points;
    std::vector<Exclusion> excluded;
    const size_t max_excluded = std::max<size_t>(
        1, static_cast<size_t>(oo.max_fraction * static_cast<double>(points.size())));
    while (true) {
        CalibrationFit out = FitOrFallBack(kept, quantity, o);
        out.excluded = excluded;
        if (!out.fit.ok() || !oo.enabled) {
            out.outlier_check = oo.enabled ? "not checked: no fit" : "not checked (disabled)";
            return out;
        }
        const Screen s = ScreenOnce(kept, quantity, o, oo.family_alpha);
        if (!s.can_check) {
            out.outlier_check = s.why_not;
            return out;
        }
        const Exclusion& w = s.worst_point;
        if (s.worst_ratio <= 1.0 || excluded.size() >= max_excluded) {
            out.outlier_check =
                "checked " + std::to_string(s.tested) + " points: largest |t| " +
                text::Sig(std::abs(w.statistic), 3) + " (point " + std::to_string(w.id) + ")" +
                (s.worst_ratio <= 1.0 ? " within " : " beyond ") + "the threshold " +
                text::Sig(w.threshold, 3) +
                (s.worst_ratio <= 1.0 ? "" : ", but the exclusion limit is reached");
            return out;
        }
        Exclusion x = w;
        x.reason = "leave-one-out: " + text::Sig(x.value, 7) + " at " + text::Sig(x.temp_c, 4) +
                   " degC is " + text::Sig(x.residual, 3) +
                   " from the others' prediction, t = " + text::Sig(x.statistic, 3) + " beyond +-" +
                   text::Sig(x.threshold, 3) + " (family alpha " + text::Sig(oo.family_alpha, 2) +
                   " over " + std::to_string(kept.size()) + " points)";
        excluded.push_back(x);
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(s.worst));
    }
}

}  // namespace gyrocal::fit
