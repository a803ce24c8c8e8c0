#include "processors/analysis/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "lcmtypes/text/number.hpp"
#include "processors/model/model.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

double RoundT0(double lo_c, double hi_c) { return 5.0 * std::round(0.5 * (lo_c + hi_c) / 5.0); }

// What measurement would tell two candidates apart.
std::string Separation(const std::string& a, const std::string& b) {
    std::set<std::string> s{a, b};
    auto has = [&](const char* e) { return s.count(e) > 0; };
    if (has("thermometer_lag"))
        return "ramps in both directions at two different rates through the same temperatures, "
               "far from T0 on both sides (the lag product grows with the rate and with the "
               "distance from T0, and changes sign with each)";
    if (has("temp_rate") && has("hysteresis"))
        return "ramps in both directions through the same temperatures with dwells between them "
               "(the rate term changes sign with the ramp and vanishes on a dwell; the branch term "
               "persists)";
    if (has("warmup"))
        return "a dwell at constant temperature right after power-on, or a second power cycle "
               "later in the run (the warm-up transient is then apart from the temperature "
               "changes)";
    if (has("supply"))
        return "a run with the supply voltage deliberately varied at constant temperature";
    if (has("temp_knot"))
        return "more temperature setpoints near the end of the range where the curve bends, "
               "visited from both sides";
    if (has("temp_cubic"))
        return "more temperature setpoints spread over a wider range, visited from both sides";
    if (has("temp_rate")) return "ramps at two different rates through the same temperatures";
    return "more data in which the two regressors vary independently";
}

namespace {

// n values from lo to hi, equally spaced in log, written as the term names them.
std::vector<std::string> LogGrid(double lo, double hi, int n, std::string (*name)(double)) {
    std::vector<std::string> g;
    for (int k = 0; k < n; ++k) {
        const std::string t = name(n == 1 ? lo : lo * std::pow(hi / lo, k / double(n - 1)));
        if (g.empty() || g.back() != t) g.push_back(t);
    }
    return g;
}

// Knots of a cubic spline over the inner 60 % of the still data's temperature range (an outer
// knot leaves too few bins on its far side to fit), relative to t0. With the cubic in the model
// (x - k)_+^3 and (k - x)_+^3 span the same shapes (they differ by the cubic (x - k)^3), so one
// form per knot: the one that is zero at t0 (above a knot above t0, below a knot below it), so
// that the polynomial keeps its meaning near the reference temperature.
std::vector<std::string> KnotGrid(double lo_c, double hi_c) {
    const double t0 = RoundT0(lo_c, hi_c);
    std::vector<std::string> g;
    for (int k = 0; k <= 12; ++k) {
        const double knot = lo_c + (hi_c - lo_c) * (0.2 + 0.05 * k) - t0;
        g.push_back(knot >= 0.0 ? model::KnotAboveTerm(knot) : model::KnotBelowTerm(knot));
    }
    g.erase(std::unique(g.begin(), g.end()), g.end());
    return g;
}

}  // namespace

std::vector<Candidate> OffsetCandidates(const BinnedRun& b, const AnalysisOptions& o) {
    const std::vector<Bin>& bins = b.bins();
    double lo = INFINITY, hi = -INFINITY;
    for (const Bin& x : bins) lo = std::min(lo, x.temp_c), hi = std::max(hi, x.temp_c);
    const double span_s =
        bins.empty() ? 0.0 : (bins.back().mid_utime - bins.front().mid_utime) * 1e-6;
    // Shape parameters: rate time constants from fast to a few minutes; branch widths up to a
    // third of the temperature range (a wider branch never completes a transition); warm-up up
    // to a tenth of the still span (a slower "transient" cannot be told from the sensor's own
    // slow drift in one power cycle).
    const double w_max = std::min(o.branch_width_max_c, std::max(0.5, (hi - lo) / 3.0));
    const double tau_max = std::min(o.warmup_tau_max_s, o.warmup_max_tau_fraction * span_s);
    std::vector<Candidate> c = {
        {"temp_rate", "V/(degC/s)", LogGrid(o.rate_tau_min_s, o.rate_tau_max_s, 6, model::RateTerm),
         "", false, "", true},
        {"hysteresis", "V", LogGrid(o.branch_width_min_c, w_max, 12, model::BranchTerm), "", false,
         ""},
        {"temp_cubic", "V/degC^3", {"dT^3"}, "", false, ""},
        {"supply", "V/V", {"supply"}, "", false, ""},
        {"warmup", "V",
         LogGrid(o.warmup_tau_min_s, std::max(tau_max, o.warmup_tau_min_s), 25, model::WarmupTerm),
         "", false, ""},
        // A static temperature shape beyond the cubic (an end of the range that bends away):
        // one knot of a cubic spline. Over most of the range a knot is the cubic's near twin, and
        // on a profile that turns once a branch is a static shape too: until the cubic is in,
        // the knot is the last resort of each forward step (the listed effects first); beyond
        // the cubic it competes like any candidate, so that what the cubic leaves of a bend is
        // not taken up by a listed effect first.
        {"temp_knot", "V/degC^3", KnotGrid(lo, hi), "", true, "temp_cubic"},
        // A thermometer that lags the die by L reads T - L dT/dt on a ramp: a static offset f(T)
        // then leaves f'(T) L dT/dt = (o1 + 2 o2 dT) L dT/dt. temp_rate takes o1 L; this term
        // (dT x dT/dt on the rate term's tracker) takes 2 o2 L, which otherwise the static
        // constant and slope absorb wherever the profile heats and cools unevenly.
        {"thermometer_lag", "V/(degC^2/s)",
         LogGrid(o.rate_tau_min_s, o.rate_tau_max_s, 6, model::LagProductTerm), "", false, "",
         true}};
    int ramp = 0, heat = 0, cool = 0, supply = 0;
    std::set<long> levels;
    const gyrocal_tracker_config_t def = gyrocal_tracker_config_default();
    for (size_t i = 0; i < bins.size(); ++i) {
        const model::ModelInputs in = b.Inputs(i, def);
        if (std::fabs(in.dtemp_dt_c_per_s) >= o.min_ramp_c_per_s) ++ramp;
        if (in.heating > 0.5) ++heat;
        if (in.heating < -0.5) ++cool;
        if (std::isfinite(bins[i].supply_v)) ++supply;
        levels.insert(std::lround(bins[i].temp_c / 2.0));
    }
    const int n = static_cast<int>(bins.size());
    if (ramp < o.min_ramp_bins)
        c[0].why_not = "no ramps in the still data (" + std::to_string(ramp) +
                       " bins with |dT/dt| >= " + text::Sig(o.min_ramp_c_per_s * 60, 3) +
                       " degC/min, need " + std::to_string(o.min_ramp_bins) + ")";
    if (heat < 3 || cool < 3)
        c[1].why_not = "the temperature did not move both up and down by more than " +
                       text::Sig(GYROCAL_SIGN_BRANCH_WIDTH_C, 3) + " degC (" +
                       std::to_string(heat) + " heating bins, " + std::to_string(cool) +
                       " cooling bins): no branches to compare";
    if (levels.size() < 5)
        c[2].why_not = "the still data covers fewer than 5 distinct 2-degC temperature bands (" +
                       std::to_string(levels.size()) + ")";
    if (supply < n)
        c[3].why_not = supply == 0 ? "no supply voltage recorded"
                                   : "supply voltage recorded in only " + std::to_string(supply) +
                                         " of " + std::to_string(n) + " still bins";
    if (!c[0].why_not.empty()) c[6].why_not = "needs temp_rate's dT/dt (" + c[0].why_not + ")";
    if (levels.size() < 8)
        c[5].why_not = "the still data covers fewer than 8 distinct 2-degC temperature bands (" +
                       std::to_string(levels.size()) + "): too few to place a knot beyond a cubic";
    else if (!c[2].why_not.empty())
        c[5].why_not = "temp_cubic cannot be tested, and a knot is a shape beyond it";
    const double first_on_s = bins.empty() ? INFINITY : bins.front().time_since_power_s;
    if (!(first_on_s <= 3.0 * o.warmup_tau_min_s + o.bins.bin_s))
        c[4].why_not = "no still data soon after power-on (first still bin " +
                       text::Sig(first_on_s, 3) +
                       " s after power-on): a warm-up transient cannot be seen";
    else if (!(tau_max > o.warmup_tau_min_s))
        c[4].why_not = "the still data span " + text::Sig(span_s, 3) +
                       " s is too short to tell a warm-up "
                       "transient from slow drift";
    if (!o.thermometer_lag_candidate) c.pop_back();  // thermometer_lag, last: off by default
    return c;
}

VectorXd Context::Column(const std::string& term) const { return binned->Column(term, t0)(rows); }

MatrixXd Context::Design(const std::vector<std::string>& terms) const {
    return AllDesign(terms)(rows, Eigen::all);
}

MatrixXd Context::AllDesign(const std::vector<std::string>& terms) const {
    const auto p = static_cast<Index>(terms.size());
    MatrixXd x(static_cast<Index>(binned->size()), p + nuisance_all.cols());
    for (Index j = 0; j < p; ++j) x.col(j) = binned->Column(terms[static_cast<size_t>(j)], t0);
    if (nuisance_all.cols() > 0) x.rightCols(nuisance_all.cols()) = nuisance_all;
    return x;
}

Context MakeContext(const BinnedRun& binned, std::vector<Index> rows, double t0,
                    const AnalysisOptions& o, const MatrixXd& nuisance_all) {
    Context c;
    c.binned = &binned;
    c.t0 = t0;
    if (nuisance_all.rows() == static_cast<Index>(binned.size())) c.nuisance_all = nuisance_all;
    c.y.resize(static_cast<Index>(rows.size()));
    int seg = -1;
    for (size_t k = 0; k < rows.size(); ++k) {
        const Bin& b = binned.bins()[static_cast<size_t>(rows[k])];
        c.y[static_cast<Index>(k)] = b.gyro_v;
        const bool continues = k > 0 && rows[k] == rows[k - 1] + 1 &&
                               binned.bins()[static_cast<size_t>(rows[k - 1])].segment == b.segment;
        if (!continues) ++seg;
        c.segment.push_back(seg);
    }
    c.rows = std::move(rows);
    c.hac_lag = static_cast<int>(std::lround(o.hac_lag_s / o.bins.bin_s));
    c.cv_guard = static_cast<int>(std::lround(o.cv_guard_s / o.bins.bin_s));
    c.cv_blocks = o.cv_blocks;
    return c;
}

}  // namespace gyrocal::analysis::detail
