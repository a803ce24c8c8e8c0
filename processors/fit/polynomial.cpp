#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "fit_util.hpp"

namespace gyrocal::fit {

using namespace detail;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// One point per level: weighted means of temperature and value (weights 1/sigma^2); the level's
// standard error is 1/sqrt(sum of weights). Levels in order of their first point in the input.
std::vector<FitPoint> CombineLevels(const std::vector<FitPoint>& pts, std::vector<Level> levels) {
    auto first = [](const Level& l) {
        return *std::min_element(l.members.begin(), l.members.end());
    };
    std::sort(levels.begin(), levels.end(),
              [&](const Level& a, const Level& b) { return first(a) < first(b); });
    std::vector<FitPoint> out;
    for (const Level& l : levels) {
        if (l.members.size() == 1) {
            out.push_back(pts[l.members[0]]);
            continue;
        }
        double sw = 0, st = 0, sy = 0;
        for (size_t i : l.members) {
            const double w = 1.0 / (pts[i].sigma_y * pts[i].sigma_y);
            sw += w;
            st += w * pts[i].inputs.temp_c;
            sy += w * pts[i].y;
        }
        FitPoint c = pts[first(l)];
        c.inputs.temp_c = st / sw;
        c.y = sy / sw;
        c.sigma_y = 1.0 / std::sqrt(sw);
        out.push_back(c);
    }
    return out;
}

struct Overdispersion {
    double c = model::kUnknown;  // NaN without dof
    int dof = 0;
};

// c from the reference model's chi2 and dof plus what the caller pooled (see fit.hpp).
Overdispersion EstimateOverdispersion(double reference_chi2, int reference_dof,
                                      const FitOptions& o) {
    const int own_dof = std::max(0, reference_dof);
    Overdispersion od;
    od.dof = own_dof + o.pooled_dof;
    if (od.dof > 0) od.c = ((own_dof > 0 ? reference_chi2 : 0.0) + o.pooled_chi2) / od.dof;
    return od;
}

// The QAIC tie band for one extra term (see fit.hpp): AIC's known-variance error rate
// P(chi2_1 > 4) kept with c estimated on nu dof.
double TieBand(int nu) {
    if (nu <= 0) return 2.0;
    const double alpha = std::erfc(std::sqrt(2.0));  // P(chi2_1 > 4) = P(|N(0,1)| > 2) = 0.0455
    return FOneUpperQuantile(alpha, nu) - 2.0;
}

// Fills the overdispersion fields and scales the covariance by the Birge ratio max(1, c).
void ApplyOverdispersion(FitResult& out, double reference_chi2, int reference_dof,
                         const FitOptions& o) {
    const Overdispersion od = EstimateOverdispersion(reference_chi2, reference_dof, o);
    out.reference_chi2 = reference_dof > 0 ? reference_chi2 : 0.0;
    out.reference_dof = std::max(0, reference_dof);
    out.overdispersion = od.c;
    out.overdispersion_dof = od.dof;
    out.covariance_scale = std::isfinite(od.c) ? std::max(1.0, od.c) : 1.0;
    out.model.covariance *= out.covariance_scale;
}

std::string OverdispersionNotes(const FitResult& r) {
    if (!std::isfinite(r.overdispersion))
        return "; overdispersion not estimated (no dof): covariance from the stated errors";
    return "; overdispersion c " + Fmt(r.overdispersion, 3) + " on " +
           std::to_string(r.overdispersion_dof) + " dof, covariance x" + Fmt(r.covariance_scale, 3);
}

}  // namespace

FitResult FitPolynomial(const std::vector<FitPoint>& pts, const std::string& quantity,
                        const FitOptions& o) {
    if (const std::string problem = o.Problem(); !problem.empty())
        return Refuse(Refusal::kNotApplicable, problem);
    if (auto bad = CheckFinite(pts)) return *bad;
    const std::vector<Level> levels = TemperatureLevels(Temps(pts), o.same_level_tolerance_c);
    std::vector<double> level_temps;
    for (const Level& l : levels) level_temps.push_back(l.temp_c);
    std::string listed;
    for (double t : level_temps) listed += (listed.empty() ? "" : ", ") + Fmt(t);
    if (levels.size() < 3)
        return Refuse(Refusal::kTooFewTemperatures,
                      "fewer than 3 distinct temperatures (have " + std::to_string(levels.size()) +
                          (listed.empty() ? "" : ": " + listed + " degC") + ")");
    for (size_t k = 1; k < levels.size(); ++k) {
        const double gap = levels[k].temp_c - levels[k - 1].temp_c;
        if (gap < o.min_temp_separation_c)
            return Refuse(Refusal::kTemperaturesTooClose,
                          "temperatures " + Fmt(levels[k - 1].temp_c) + " and " +
                              Fmt(levels[k].temp_c) + " degC are " + Fmt(gap, 3) +
                              " degC apart, closer than the minimum " +
                              Fmt(o.min_temp_separation_c) + " degC");
    }
    const double range = levels.back().temp_c - levels.front().temp_c;
    if (range < o.min_range_c)
        return Refuse(Refusal::kRangeTooNarrow,
                      "temperature range " + Fmt(levels.front().temp_c) + ".." +
                          Fmt(levels.back().temp_c) + " degC spans " + Fmt(range, 3) +
                          " degC, narrower than the minimum " + Fmt(o.min_range_c) +
                          " degC (a fit is only a guess outside its range)");

    const bool three_point = o.method == Method::kThreePoint ||
                             (o.method == Method::kAuto && pts.size() == 3 && o.fixed_degree == 0);
    if (three_point) {
        if (levels.size() != 3)
            return Refuse(Refusal::kNotApplicable,
                          "method 3point needs exactly 3 temperatures, have " +
                              std::to_string(levels.size()) + " (" + listed + " degC)");
        // More than one point per level (e.g. both rotation directions): the seed's point is the
        // level's weighted mean.
        FitResult out = SeedThreePoint(CombineLevels(pts, levels), quantity);
        out.used_ids = Ids(pts);
        out.level_temps_c = level_temps;
        if (out.ok()) out.model.n_points = static_cast<int32_t>(pts.size());
        return out;
    }

    const double t0 =
        o.t0_c ? *o.t0_c
               : 5.0 * std::round(0.5 * (levels.front().temp_c + levels.back().temp_c) / 5.0);
    const int n = static_cast<int>(pts.size());
    const int capacity = std::min({static_cast<int>(levels.size()) - 1, n - 2, o.max_degree});
    if (o.fixed_degree > 0) {
        if (o.fixed_degree > std::min(static_cast<int>(levels.size()) - 1, n - 2))
            return Refuse(Refusal::kNotApplicable,
                          "degree " + std::to_string(o.fixed_degree) + " needs at least " +
                              std::to_string(o.fixed_degree + 1) + " temperatures and " +
                              std::to_string(o.fixed_degree + 2) + " points; have " +
                              std::to_string(levels.size()) + " and " + std::to_string(n));
        FitResult out = FitWls(pts, model::PolynomialTerms(o.fixed_degree), t0, quantity,
                               o.max_condition_number);
        out.level_temps_c = level_temps;
        if (out.ok()) {
            ApplyOverdispersion(out, out.chi2, out.dof, o);
            out.detail = "degree " + std::to_string(o.fixed_degree) + " fixed by option" +
                         FitNotes(out) + OverdispersionNotes(out);
        }
        return out;
    }
    if (capacity < 1)
        return Refuse(Refusal::kNotApplicable,
                      "wls needs at least 3 points for a line with one degree of freedom");

    std::vector<FitResult> fits;
    std::vector<DegreeCandidate> candidates;
    for (int d = 1; d <= capacity; ++d) {
        FitResult f = FitWls(pts, model::PolynomialTerms(d), t0, quantity, o.max_condition_number);
        if (!f.ok()) continue;
        candidates.push_back({d, f.chi2, f.chi2 + 2.0 * (d + 1)});
        fits.push_back(std::move(f));
    }
    if (fits.empty()) {
        FitResult why =
            FitWls(pts, model::PolynomialTerms(1), t0, quantity, o.max_condition_number);
        why.level_temps_c = level_temps;
        return why;
    }
    // The reference model is the largest candidate that could be fitted (see fit.hpp).
    const FitResult& reference = fits.back();
    const Overdispersion od = EstimateOverdispersion(reference.chi2, reference.dof, o);
    const double c_select = std::isfinite(od.c) ? std::max(1.0, od.c) : 1.0;
    const double band = TieBand(od.dof);
    for (DegreeCandidate& c : candidates) c.aic = c.chi2 / c_select + 2.0 * (c.degree + 1);
    double best_aic = std::numeric_limits<double>::infinity();
    for (const DegreeCandidate& c : candidates) best_aic = std::min(best_aic, c.aic);
    // QAIC values within the band of the best are a tie (see header); ties go to the quadratic,
    // else to the lowest degree.
    size_t chosen = candidates.size();
    for (size_t k = 0; k < candidates.size(); ++k)
        if (candidates[k].aic - best_aic <= band && candidates[k].degree == 2) chosen = k;
    if (chosen == candidates.size())
        for (size_t k = 0; k < candidates.size() && chosen == candidates.size(); ++k)
            if (candidates[k].aic - best_aic <= band) chosen = k;
    const double reference_chi2 = reference.chi2;
    const int reference_dof = reference.dof;
    FitResult out = std::move(fits[chosen]);
    out.candidates = candidates;
    out.level_temps_c = level_temps;
    ApplyOverdispersion(out, reference_chi2, reference_dof, o);
    std::ostringstream why;
    why << "degree " << candidates[chosen].degree << (od.dof > 0 ? " by QAIC (" : " by AIC (");
    for (size_t k = 0; k < candidates.size(); ++k)
        why << (k ? ", " : "") << "d" << candidates[k].degree << "=" << Fmt(candidates[k].aic, 5);
    why << "; tie band " << Fmt(band, 3) << "; capacity " << capacity << ")";
    out.detail = why.str() + FitNotes(out) + OverdispersionNotes(out);
    return out;
}

}  // namespace gyrocal::fit
