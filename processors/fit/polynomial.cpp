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
        if (out.ok())
            out.detail =
                "degree " + std::to_string(o.fixed_degree) + " fixed by option" + FitNotes(out);
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
    double best_aic = std::numeric_limits<double>::infinity();
    for (const DegreeCandidate& c : candidates) best_aic = std::min(best_aic, c.aic);
    // AIC values within 2 of the best are a tie (see header); ties go to the quadratic, else to
    // the lowest degree.
    size_t chosen = candidates.size();
    for (size_t k = 0; k < candidates.size(); ++k)
        if (candidates[k].aic - best_aic <= 2.0 && candidates[k].degree == 2) chosen = k;
    if (chosen == candidates.size())
        for (size_t k = 0; k < candidates.size() && chosen == candidates.size(); ++k)
            if (candidates[k].aic - best_aic <= 2.0) chosen = k;
    FitResult out = std::move(fits[chosen]);
    out.candidates = candidates;
    out.level_temps_c = level_temps;
    std::ostringstream why;
    why << "degree " << candidates[chosen].degree << " by AIC (";
    for (size_t k = 0; k < candidates.size(); ++k)
        why << (k ? ", " : "") << "d" << candidates[k].degree << "=" << Fmt(candidates[k].aic, 5);
    why << "; capacity " << capacity << ")";
    out.detail = why.str() + FitNotes(out);
    return out;
}

}  // namespace gyrocal::fit
