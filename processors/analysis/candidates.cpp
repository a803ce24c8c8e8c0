#include "candidates.hpp"

#include <cmath>
#include <cstdio>
#include <set>

#include "model/model.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

std::string Fmt(double v, int prec) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    return buf;
}

double RoundT0(double lo_c, double hi_c) { return 5.0 * std::round(0.5 * (lo_c + hi_c) / 5.0); }

MatrixXd Design(const std::vector<std::string>& terms, double t0_c, const std::vector<Bin>& bins,
                int64_t first_utime) {
    const std::vector<model::ResolvedTerm> resolved = model::ResolveTerms(terms);
    MatrixXd x(static_cast<Index>(bins.size()), static_cast<Index>(terms.size()));
    for (size_t i = 0; i < bins.size(); ++i)
        x.row(static_cast<Index>(i)) =
            model::TermValues(resolved, t0_c, bins[i].Inputs(first_utime)).transpose();
    return x;
}

VectorXd Column(const std::string& term, double t0_c, const std::vector<Bin>& bins,
                int64_t first_utime) {
    return Design({term}, t0_c, bins, first_utime).col(0);
}

std::string WarmupTerm(double tau_s) { return "warmup(" + Fmt(tau_s, 3) + ")"; }

// What measurement would tell two candidates apart.
std::string Separation(const std::string& a, const std::string& b) {
    std::set<std::string> s{a, b};
    auto has = [&](const char* e) { return s.count(e) > 0; };
    if (has("temp_rate") && has("hysteresis"))
        return "ramps in both directions through the same temperatures with dwells between them "
               "(the rate term changes sign with the ramp and vanishes on a dwell; the branch term "
               "persists)";
    if (has("warmup"))
        return "a dwell at constant temperature right after power-on, or a second power cycle "
               "later in "
               "the run (the warm-up transient is then apart from the temperature changes)";
    if (has("supply"))
        return "a run with the supply voltage deliberately varied at constant temperature";
    if (has("temp_cubic"))
        return "more temperature setpoints spread over a wider range, visited from both sides";
    if (has("temp_rate")) return "ramps at two different rates through the same temperatures";
    return "more data in which the two regressors vary independently";
}

std::vector<Candidate> OffsetCandidates(const SensorRun& run, const std::vector<Bin>& bins,
                                        const AnalysisOptions& o) {
    std::vector<Candidate> c = {{"temp_rate", "dTdt", "V/(degC/s)", false, ""},
                                {"hysteresis", "heating", "V", false, ""},
                                {"temp_cubic", "dT^3", "V/degC^3", false, ""},
                                {"supply", "supply", "V/V", false, ""},
                                {"warmup", "warmup", "V", true, ""}};
    int ramp = 0, heat = 0, cool = 0, supply = 0;
    std::set<long> levels;
    for (const Bin& b : bins) {
        if (std::fabs(b.dtemp_dt_c_per_s) >= o.min_ramp_c_per_s) ++ramp;
        if (b.heating > 0) ++heat;
        if (b.heating < 0) ++cool;
        if (std::isfinite(b.supply_v)) ++supply;
        levels.insert(std::lround(b.temp_c / 2.0));
    }
    const int n = static_cast<int>(bins.size());
    if (ramp < o.min_ramp_bins)
        c[0].why_not = "no ramps in the still data (" + std::to_string(ramp) +
                       " bins with |dT/dt| >= " + Fmt(o.min_ramp_c_per_s * 60) +
                       " degC/min, need " + std::to_string(o.min_ramp_bins) + ")";
    if (heat < 3 || cool < 3)
        c[1].why_not = "the temperature did not move both up and down by more than " +
                       Fmt(o.bins.branch_width_c) + " degC (" + std::to_string(heat) +
                       " heating bins, " + std::to_string(cool) +
                       " cooling bins): no branches to compare";
    if (levels.size() < 5)
        c[2].why_not = "the still data covers fewer than 5 distinct 2-degC temperature bands (" +
                       std::to_string(levels.size()) + ")";
    if (supply < n)
        c[3].why_not = supply == 0 ? "no supply voltage recorded"
                                   : "supply voltage recorded in only " + std::to_string(supply) +
                                         " of " + std::to_string(n) + " still bins";
    const double first_on_s =
        bins.empty() ? INFINITY : bins.front().Inputs(run.first_sample_utime).time_since_power_s;
    if (!(first_on_s <= 3.0 * o.warmup_tau_min_s + o.bins.bin_s))
        c[4].why_not = "no still data soon after power-on (first still bin " + Fmt(first_on_s) +
                       " s after the first sample): a warm-up transient cannot be seen";
    return c;
}

}  // namespace gyrocal::analysis::detail
