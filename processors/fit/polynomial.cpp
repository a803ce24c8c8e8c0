#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/fit_util.hpp"

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

// The QAIC tie band for one extra term (see fit.hpp): AIC's known-variance error rate
// P(chi2_1 > 4) kept with c estimated on nu dof.
double TieBand(int nu) {
    if (nu <= 0) return 2.0;
    const double alpha = std::erfc(std::sqrt(2.0));  // P(chi2_1 > 4) = P(|N(0,1)| > 2) = 0.0455
    return FOneUpperQuantile(alpha, nu) - 2.0;
}

std::string Listed(const std::vector<double>& temps) {
    std::string listed;
    for (double t : temps) listed += (listed.empty() ? "" : ", ") + text::Sig(t, 4);
    return listed;
}

// The point set's geometry: levels (replicates merged), how many are far enough apart to carry
// a degree, and the refusal when a temperature model cannot be fitted at all.
struct Geometry {
    std::vector<Level> levels;
    std::vector<double> level_temps;
    int separated = 0;
    std::optional<FitResult> refusal;
};

Geometry CheckGeometry(const std::vector<FitPoint>& pts, const FitOptions& o) {
    Geometry g;
    g.levels = TemperatureLevels(Temps(pts), o.same_level_tolerance_c);
    for (const Level& l : g.levels) g.level_temps.push_back(l.temp_c);
    g.separated = SeparatedLevelCount(g.levels, o.min_temp_separation_c);
    const std::string listed = Listed(g.level_temps);
    if (g.separated < 3) {
        g.refusal =
            Refuse(Refusal::kTooFewTemperatures,
                   "fewer than 3 temperatures at least " + text::Sig(o.min_temp_separation_c, 4) +
                       " degC apart (have " + std::to_string(g.separated) + " among " +
                       std::to_string(g.levels.size()) + " levels" +
                       (listed.empty() ? "" : ": " + listed + " degC") + ")");
        return g;
    }
    const double range = g.levels.back().temp_c - g.levels.front().temp_c;
    if (range < o.min_range_c)
        g.refusal =
            Refuse(Refusal::kRangeTooNarrow,
                   "temperature range " + text::Sig(g.levels.front().temp_c, 4) + ".." +
                       text::Sig(g.levels.back().temp_c, 4) + " degC spans " + text::Sig(range, 3) +
                       " degC, narrower than the minimum " + text::Sig(o.min_range_c, 4) +
                       " degC (a fit is only a guess outside its range)");
    return g;
}

FitResult ThreePoint(const std::vector<FitPoint>& pts, const Geometry& g,
                     const std::string& quantity) {
    if (g.levels.size() != 3)
        return Refuse(Refusal::kNotApplicable, "method 3point needs exactly 3 temperatures, have " +
                                                   std::to_string(g.levels.size()) + " (" +
                                                   Listed(g.level_temps) + " degC)");
    // More than one point per level (e.g. both rotation directions): the seed's point is the
    // level's weighted mean.
    FitResult out = SeedThreePoint(CombineLevels(pts, g.levels), quantity);
    out.used_ids = Ids(pts);
    out.level_temps_c = g.level_temps;
    if (out.ok()) out.model.n_points = static_cast<int32_t>(pts.size());
    return out;
}

FitResult FixedDegree(const std::vector<FitPoint>& pts, const Geometry& g, double t0,
                      const std::string& quantity, const FitOptions& o) {
    const int n = static_cast<int>(pts.size());
    if (o.fixed_degree > std::min(g.separated - 1, n - 2))
        return Refuse(Refusal::kNotApplicable,
                      "degree " + std::to_string(o.fixed_degree) + " needs at least " +
                          std::to_string(o.fixed_degree + 1) + " temperatures " +
                          text::Sig(o.min_temp_separation_c, 4) + " degC apart and " +
                          std::to_string(o.fixed_degree + 2) + " points; have " +
                          std::to_string(g.separated) + " and " + std::to_string(n));
    FitResult out =
        FitWls(pts, model::PolynomialTerms(o.fixed_degree), t0, quantity, o.max_condition_number);
    out.level_temps_c = g.level_temps;
    if (out.ok()) {
        ApplyOverdispersion(out, out.chi2, out.dof, o);
        out.detail = "degree " + std::to_string(o.fixed_degree) + " fixed by option" +
                     FitNotes(out) + OverdispersionNotes(out);
    }
    return out;
}

// QAIC values within the band of the best are a tie (see fit.hpp); ties go to the quadratic,
// else to the lowest degree.
size_t ChooseDegree(std::vector<DegreeCandidate>& candidates, double c_select, double band) {
    for (DegreeCandidate& c : candidates) c.aic = c.chi2 / c_select + 2.0 * (c.degree + 1);
    double best_aic = std::numeric_limits<double>::infinity();
    for (const DegreeCandidate& c : candidates) best_aic = std::min(best_aic, c.aic);
    size_t chosen = candidates.size();
    for (size_t k = 0; k < candidates.size(); ++k)
        if (candidates[k].aic - best_aic <= band && candidates[k].degree == 2) chosen = k;
    if (chosen == candidates.size())
        for (size_t k = 0; k < candidates.size() && chosen == candidates.size(); ++k)
            if (candidates[k].aic - best_aic <= band) chosen = k;
    return chosen;
}

FitResult SelectOrder(const std::vector<FitPoint>& pts, const Geometry& g, double t0,
                      const std::string& quantity, const FitOptions& o) {
    const int n = static_cast<int>(pts.size());
    const int capacity = std::min({g.separated - 1, n - 2, o.max_degree});
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
        why.level_temps_c = g.level_temps;
        return why;
    }
    // The reference model is the largest candidate that could be fitted (see fit.hpp).
    const double reference_chi2 = fits.back().chi2;
    const int reference_dof = fits.back().dof;
    const Overdispersion od = EstimateOverdispersion(reference_chi2, reference_dof, o);
    const double band = TieBand(od.dof);
    const size_t chosen =
        ChooseDegree(candidates, std::isfinite(od.c) ? std::max(1.0, od.c) : 1.0, band);
    FitResult out = std::move(fits[chosen]);
    out.candidates = candidates;
    out.level_temps_c = g.level_temps;
    ApplyOverdispersion(out, reference_chi2, reference_dof, o);
    std::ostringstream why;
    why << "degree " << candidates[chosen].degree << (od.dof > 0 ? " by QAIC (" : " by AIC (");
    for (size_t k = 0; k < candidates.size(); ++k)
        why << (k ? ", " : "") << "d" << candidates[k].degree << "="
            << text::Sig(candidates[k].aic, 5);
    why << "; tie band " << text::Sig(band, 3) << "; capacity " << capacity << ")";
    out.detail = why.str() + FitNotes(out) + OverdispersionNotes(out);
    return out;
}

}  // namespace

double DefaultT0(double coldest_c, double hottest_c) {
    return 5.0 * std::round(0.5 * (coldest_c + hottest_c) / 5.0);
}

FitResult FitPolynomial(const std::vector<FitPoint>& pts, const std::string& quantity,
                        const FitOptions& o) {
    if (const std::string problem = o.Validate(); !problem.empty())
        return Refuse(Refusal::kNotApplicable, problem);
    if (auto bad = CheckFinite(pts)) return *bad;
    const Geometry g = CheckGeometry(pts, o);
    if (g.refusal) return *g.refusal;
    const bool three_point = o.method == Method::kThreePoint ||
                             (o.method == Method::kAuto && pts.size() == 3 && o.fixed_degree == 0);
    if (three_point) return ThreePoint(pts, g, quantity);
    const double t0 = o.t0_c ? *o.t0_c : DefaultT0(g.levels.front().temp_c, g.levels.back().temp_c);
    if (o.fixed_degree > 0) return FixedDegree(pts, g, t0, quantity, o);
    return SelectOrder(pts, g, t0, quantity, o);
}

}  // namespace gyrocal::fit
