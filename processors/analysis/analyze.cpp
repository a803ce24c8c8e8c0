#include "analyze.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>

#include "fit/fit.hpp"
#include "fit/levels.hpp"
#include "regress.hpp"
#include "sensitivity.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

const char* ToString(Decision d) {
    switch (d) {
        case Decision::kAdded:
            return "added";
        case Decision::kRejected:
            return "rejected";
        case Decision::kAmbiguous:
            return "ambiguous";
        case Decision::kNotTested:
            return "not_tested";
    }
    return "?";
}

std::string AnalysisOptions::Problem() const {
    if (!(bins.bin_s > 0.0 && bins.bin_s <= 600.0)) return "bin_s must be in (0, 600] s";
    if (!(bins.min_fill > 0.0 && bins.min_fill <= 1.0)) return "min_fill must be in (0, 1]";
    if (!(bins.branch_width_c > 0.0)) return "branch_width_c must be > 0";
    if (offset_terms.empty()) return "offset_terms must not be empty";
    if (sensitivity_terms.empty()) return "sensitivity_terms must not be empty";
    for (const auto* list : {&offset_terms, &sensitivity_terms})
        for (const std::string& t : *list) {
            std::string error;
            if (!model::ResolveTerm(t, nullptr, &error)) return "declared model: " + error;
        }
    if (!(min_z2 > 0.0)) return "min_z2 must be > 0";
    if (!(min_cv_gain >= 0.0 && min_cv_gain < 1.0)) return "min_cv_gain must be in [0, 1)";
    if (cv_blocks < 3 || cv_blocks > 100) return "cv_blocks must be 3..100";
    if (!(cv_guard_s >= 0.0) || !(hac_lag_s >= 0.0)) return "cv_guard_s and hac_lag_s must be >= 0";
    if (!(max_collinearity > 0.0 && max_collinearity < 1.0))
        return "max_collinearity must be in (0, 1)";
    if (!(holdout_fraction > 0.0 && holdout_fraction < 0.9))
        return "holdout_fraction must be in (0, 0.9)";
    if (!(warmup_tau_min_s > 0.0 && warmup_tau_max_s > warmup_tau_min_s))
        return "warmup tau range must satisfy 0 < min < max";
    return "";
}

namespace {

std::string Fmt(double v, int prec = 3) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    return buf;
}

double RoundT0(double lo_c, double hi_c) { return 5.0 * std::round(0.5 * (lo_c + hi_c) / 5.0); }

struct Candidate {
    std::string effect, term, unit;
    bool search_tau = false;
    std::string why_not;  // "" = testable
};

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

struct StepScore {
    double z2 = 0.0, cv_gain = 0.0, coef = 0.0, var = 0.0, rss = INFINITY;
    double effect_rms_v = 0.0;  // |coef| * RMS of the regressor after projecting out the model
    std::string term;
    VectorXd column;
    bool ok = false;
};

struct Context {
    const std::vector<Bin>* bins;
    int64_t first_utime;
    double t0;
    VectorXd y;
    std::vector<int> segment;
    int hac_lag, cv_guard, cv_blocks;
};

StepScore Score(const Context& c, const MatrixXd& x, double base_cv, const Candidate& cand,
                const AnalysisOptions& o, const VectorXd* noise = nullptr, int noise_params = 0) {
    StepScore s;
    const Index p = x.cols();
    MatrixXd xe(x.rows(), p + 1);
    xe.leftCols(p) = x;
    s.term = cand.term;
    if (cand.search_tau) {
        // 1-D search of tau on a log grid (ratio ~1.2 between points): the residual sum of squares
        // is smooth in log(tau), and 25 fits of a few hundred bins cost nothing.
        // tau is capped at a tenth of the still data's span: a slower "transient" cannot be told
        // from the sensor's own slow drift (bias instability, rate random walk) in one power cycle.
        const double span_s = (c.bins->back().mid_utime - c.bins->front().mid_utime) * 1e-6;
        const double tau_max = std::min(o.warmup_tau_max_s, o.warmup_max_tau_fraction * span_s);
        if (!(tau_max > o.warmup_tau_min_s)) return s;
        double best_rss = INFINITY;
        const int n_grid = 25;
        for (int k = 0; k < n_grid; ++k) {
            const double tau =
                o.warmup_tau_min_s * std::pow(tau_max / o.warmup_tau_min_s, k / double(n_grid - 1));
            const std::string term = WarmupTerm(tau);
            xe.col(p) = Column(term, c.t0, *c.bins, c.first_utime);
            const LsFit f = FitLs(xe, c.y, c.segment, 0);
            if (f.ok && f.rss < best_rss) {
                best_rss = f.rss;
                s.term = term;
            }
        }
        if (!std::isfinite(best_rss)) return s;
    }
    s.column = Column(s.term, c.t0, *c.bins, c.first_utime);
    xe.col(p) = s.column;
    const LsFit f = FitLs(xe, c.y, c.segment, c.hac_lag, noise, noise_params);
    if (!f.ok) return s;
    s.coef = f.coeffs[p];
    s.var = f.covariance(p, p);
    s.rss = f.rss;
    {
        const VectorXd sc = x.colwise().norm().cwiseMax(1e-300);
        const MatrixXd xs = x * sc.cwiseInverse().asDiagonal();
        const VectorXd proj = s.column - xs * xs.colPivHouseholderQr().solve(s.column);
        s.effect_rms_v =
            std::fabs(s.coef) * proj.norm() / std::sqrt(static_cast<double>(proj.size()));
    }
    s.z2 = s.coef * s.coef / s.var;
    const double cv = BlockedCvMse(xe, c.y, c.cv_blocks, c.cv_guard);
    if (!std::isfinite(cv) || !(base_cv > 0.0)) return s;
    s.cv_gain = (base_cv - cv) / base_cv;
    s.ok = true;
    return s;
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

void ErrorsOn(const std::vector<Bin>& hold, const model::Evaluator& offset,
              const std::optional<model::Evaluator>& sens, double period_s, int64_t first_utime,
              ErrorFigures* e) {
    double ss_v = 0.0, ss_r = 0.0, angle = 0.0, dur = 0.0;
    int n = 0;
    bool rate_ok = sens.has_value();
    for (const Bin& b : hold) {
        const model::ModelInputs in = b.Inputs(first_utime);
        const double r = b.gyro_v - offset.Value(in, model::RangePolicy::kExtrapolate);
        if (!std::isfinite(r)) continue;
        ss_v += r * r;
        ++n;
        if (rate_ok) {
            model::ModelInputs si = in;
            si.direction = 0.0;  // at rest: no rotation direction (a direction term contributes 0)
            const double s = sens->Value(si, model::RangePolicy::kClip);
            if (!std::isfinite(s) || s == 0.0) {
                rate_ok = false;
                continue;
            }
            const double rate = r / s;
            ss_r += rate * rate;
            const double d = b.n * period_s;
            angle += rate * d;
            dur += d;
        }
    }
    if (n == 0) return;
    e->offset_rms_v = std::sqrt(ss_v / n);
    if (rate_ok && dur > 0) {
        e->rate_rms_dps = std::sqrt(ss_r / n);
        e->drift_dph = std::fabs(angle) / dur * 3600.0;
    }
}

std::vector<fit::FitPoint> PlateauPoints(const std::vector<PlateauInput>& plateaus,
                                         int64_t before_utime) {
    std::vector<fit::FitPoint> pts;
    for (const PlateauInput& p : plateaus) {
        if (p.end_utime > before_utime) continue;
        if (!std::isfinite(p.temp_mean_c) || !std::isfinite(p.gyro_mean_v) || !(p.gyro_sem_v > 0.0))
            continue;
        fit::FitPoint f;
        f.inputs.temp_c = p.temp_mean_c;
        f.y = p.gyro_mean_v;
        f.sigma_y = p.gyro_sem_v;
        f.id = p.plateau_id;
        pts.push_back(f);
    }
    return pts;
}

// The declared offset model on plateau means; nullopt with `why` when it cannot be fitted.
std::optional<model::Model> DeclaredOffset(const std::vector<fit::FitPoint>& pts,
                                           const AnalysisOptions& o, std::string* why) {
    std::vector<double> temps;
    for (const auto& p : pts) temps.push_back(p.inputs.temp_c);
    const auto levels = fit::TemperatureLevels(temps, o.same_level_tolerance_c);
    if (levels.size() < o.offset_terms.size()) {
        *why = "fewer plateau temperatures (" + std::to_string(levels.size()) +
               ") than declared offset terms (" + std::to_string(o.offset_terms.size()) + ")";
        return std::nullopt;
    }
    const fit::FitResult f =
        fit::FitWls(pts, o.offset_terms, RoundT0(levels.front().temp_c, levels.back().temp_c),
                    model::kOffsetQuantity);
    if (!f.ok()) {
        *why = f.detail;
        return std::nullopt;
    }
    return f.model;
}

// Model from a bin fit.
model::Model BinModel(const std::vector<std::string>& terms, double t0,
                      const std::vector<Bin>& bins, const LsFit& f) {
    model::Model m;
    m.quantity = model::kOffsetQuantity;
    m.term_names = terms;
    m.coeffs = f.coeffs;
    m.covariance = f.covariance;
    m.t0_c = t0;
    m.temp_min_c = INFINITY;
    m.temp_max_c = -INFINITY;
    for (const Bin& b : bins) {
        m.temp_min_c = std::min(m.temp_min_c, b.temp_c);
        m.temp_max_c = std::max(m.temp_max_c, b.temp_c);
    }
    m.residual_rms = std::sqrt(f.rss / static_cast<double>(bins.size()));
    m.n_points = static_cast<int32_t>(bins.size());
    m.method = "analysis";
    return m;
}

}  // namespace

SensorResult Analyze(const SensorRun& run, const AnalysisOptions& o) {
    if (const std::string p = o.Problem(); !p.empty())
        throw std::invalid_argument("analysis options: " + p);
    SensorResult res;
    res.sensor_id = run.sensor_id;
    res.bin_s = o.bins.bin_s;
    const std::vector<Bin> bins = MakeBins(run, o.bins);
    res.n_bins = static_cast<int>(bins.size());
    const double period_s = SamplePeriodS(run);
    if (!run.has_encoder)
        res.notes.push_back(
            "no encoder readings: table motion could not be excluded, every sample counted as "
            "still");
    if (run.n_seq_gaps > 0)
        res.notes.push_back(std::to_string(run.n_seq_gaps) +
                            " samples missing by sequence number (bins with gaps dropped)");
    if (run.n_bad_samples > 0)
        res.notes.push_back(std::to_string(run.n_bad_samples) +
                            " samples non-finite or out of order (excluded)");
    if (!bins.empty() && bins.back().segment > 0)
        res.notes.push_back("still data in " + std::to_string(bins.back().segment + 1) +
                            " contiguous stretches (moves and gaps split it)");

    // Sensitivity: declared model (for deg/s) and the sf_asymmetry candidate.
    const SensitivityOutcome so = AnalyzeSensitivity(run.sensitivities, o);
    res.n_sensitivity_points = so.n_points;
    res.declared_sensitivity = so.declared;
    res.extended_sensitivity = so.extended;
    res.sens_rel_rms_before = so.rel_rms_before;
    res.sens_rel_rms_after = so.rel_rms_after;
    res.sens_chi2_dof_before = so.chi2_dof_before;
    res.sens_chi2_dof_after = so.chi2_dof_after;
    if (!so.problem.empty())
        res.could_not_test.push_back("rates in deg/s and sf_asymmetry: " + so.problem);
    std::optional<model::Evaluator> sens;
    if (so.declared) sens.emplace(*so.declared);

    // Declared offset model on all plateaus, its residual on all still bins.
    const std::vector<fit::FitPoint> all_plateaus = PlateauPoints(run.plateaus, INT64_MAX);
    res.n_plateaus_used = static_cast<int>(all_plateaus.size());
    std::string why;
    res.declared_offset = DeclaredOffset(all_plateaus, o, &why);
    if (!res.declared_offset)
        res.could_not_test.push_back("declared offset model (" +
                                     std::to_string(all_plateaus.size()) +
                                     " usable plateaus): " + why + "; error before not computed");
    const Floor floor = NoiseFloor(run, bins, o.bins.bin_s);
    res.floor_offset_rms_v = floor.offset_rms_v;
    if (!std::isfinite(floor.offset_rms_v))
        res.could_not_test.push_back(
            "noise floor: no plateau window holds 3 bins and no plateau standard error");
    else if (floor.from_standard_errors)
        res.notes.push_back(
            "noise floor from plateau standard errors (white-noise assumption): no plateau holds 3 "
            "bins");

    std::vector<CandidateResult> cands_out;
    const int min_bins = 3 * o.cv_blocks + 10;
    if (static_cast<int>(bins.size()) < min_bins) {
        res.could_not_test.push_back("offset candidates: " + std::to_string(bins.size()) +
                                     " still bins of " + Fmt(o.bins.bin_s) + " s, need " +
                                     std::to_string(min_bins));
        for (const char* e : {"temp_rate", "hysteresis", "temp_cubic", "supply", "warmup"})
            cands_out.push_back(
                {e, "", Decision::kNotTested, kNan, kNan, 0, "too few still bins", kNan});
    }
    double t0 = 25.0;
    if (res.declared_offset)
        t0 = res.declared_offset->t0_c;
    else if (!bins.empty()) {
        double lo = INFINITY, hi = -INFINITY;
        for (const Bin& b : bins) lo = std::min(lo, b.temp_c), hi = std::max(hi, b.temp_c);
        t0 = RoundT0(lo, hi);
    }
    if (res.declared_offset && !bins.empty()) {
        const model::Evaluator ev(*res.declared_offset);
        double ss = 0;
        for (const Bin& b : bins) {
            const double r = b.gyro_v - ev.Value(b.Inputs(run.first_sample_utime),
                                                 model::RangePolicy::kExtrapolate);
            ss += r * r;
        }
        res.residual_all_rms_v = std::sqrt(ss / bins.size());
    }

    std::vector<std::string> terms = o.offset_terms;
    std::vector<std::string> added_effects;
    std::vector<std::string> ambiguous;
    if (static_cast<int>(bins.size()) >= min_bins) {
        Context c;
        c.bins = &bins;
        c.first_utime = run.first_sample_utime;
        c.t0 = t0;
        c.y.resize(static_cast<Index>(bins.size()));
        for (size_t i = 0; i < bins.size(); ++i) {
            c.y[static_cast<Index>(i)] = bins[i].gyro_v;
            c.segment.push_back(bins[i].segment);
        }
        c.hac_lag = static_cast<int>(std::lround(o.hac_lag_s / o.bins.bin_s));
        c.cv_guard = static_cast<int>(std::lround(o.cv_guard_s / o.bins.bin_s));
        c.cv_blocks = o.cv_blocks;
        std::vector<Candidate> pool;
        for (const Candidate& cand : OffsetCandidates(run, bins, o)) {
            if (cand.why_not.empty())
                pool.push_back(cand);
            else {
                cands_out.push_back({cand.effect, cand.term, Decision::kNotTested, kNan, kNan, 0,
                                     cand.why_not, kNan});
                res.could_not_test.push_back(cand.effect + ": " + cand.why_not);
            }
        }
        std::map<std::string, CandidateResult> last;  // latest statistics of each pool candidate
        MatrixXd x = Design(terms, t0, bins, c.first_utime);
        for (int step = 1; !pool.empty(); ++step) {
            const double base_cv = BlockedCvMse(x, c.y, c.cv_blocks, c.cv_guard);
            // First pass: each candidate's column (warm-up tau searched). The noise for the tests
            // is the residual of the model with ALL remaining candidates in (when it can be
            // fitted), so a second missing effect does not pass for noise while the first is
            // tested.
            std::vector<StepScore> scores;
            MatrixXd xfull = x;
            for (size_t k = 0; k < pool.size(); ++k) {
                scores.push_back(Score(c, x, base_cv, pool[k], o));
                if (scores.back().column.size() == 0) continue;
                MatrixXd xn(xfull.rows(), xfull.cols() + 1);
                xn << xfull, scores.back().column;
                xfull = xn;
            }
            const LsFit full = FitLs(xfull, c.y, c.segment, 0);
            const VectorXd* noise = full.ok ? &full.residuals : nullptr;
            int best = -1;
            for (size_t k = 0; k < pool.size(); ++k) {
                if (noise)
                    scores[k] =
                        Score(c, x, base_cv, pool[k], o, noise, static_cast<int>(xfull.cols()));
                const StepScore& s = scores[k];
                CandidateResult& r = last[pool[k].effect];
                r = {pool[k].effect, s.term, Decision::kRejected, s.z2, s.cv_gain,
                     step,           "",     s.effect_rms_v};
                if (!s.ok) r.note = "could not be fitted with the current model";
                const bool big_enough =
                    !std::isfinite(floor.offset_rms_v) ||
                    s.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
                if (s.ok && !big_enough)
                    r.note = "effect RMS " + Fmt(s.effect_rms_v) + " V is below " +
                             Fmt(o.min_effect_floor_ratio) + "x the noise floor " +
                             Fmt(floor.offset_rms_v) + " V";
                const bool pass =
                    s.ok && s.z2 > o.min_z2 && s.cv_gain > o.min_cv_gain && big_enough;
                // The best explains the most (smallest residual sum of squares), not the largest
                // z^2: a candidate correlated with a stronger missing effect borrows its signal.
                if (pass && (best < 0 || s.rss < scores[static_cast<size_t>(best)].rss))
                    best = static_cast<int>(k);
            }
            if (best < 0) break;
            const auto b = static_cast<size_t>(best);
            std::vector<size_t> twins;
            for (size_t k = 0; k < pool.size(); ++k) {
                if (k == b || scores[k].column.size() == 0) continue;
                const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
                if (std::isfinite(r) && std::fabs(r) > o.max_collinearity) twins.push_back(k);
            }
            if (!twins.empty()) {
                std::vector<size_t> drop = twins;
                drop.push_back(b);
                for (size_t k : twins) {
                    const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
                    for (size_t i : {b, k}) {
                        CandidateResult& cr = last[pool[i].effect];
                        cr.decision = Decision::kAmbiguous;
                        const std::string other = pool[i == b ? k : b].effect;
                        cr.note += (cr.note.empty() ? "" : "; ") + std::string("ambiguous with ") +
                                   other + " (projected correlation " + Fmt(r, 3) +
                                   "); to separate: " + Separation(pool[b].effect, pool[k].effect);
                    }
                    ambiguous.push_back(pool[b].effect + " vs " + pool[k].effect);
                }
                std::sort(drop.rbegin(), drop.rend());
                for (size_t k : drop) pool.erase(pool.begin() + static_cast<long>(k));
                continue;
            }
            last[pool[b].effect].decision = Decision::kAdded;
            terms.push_back(scores[b].term);
            added_effects.push_back(pool[b].effect);
            MatrixXd xn(x.rows(), x.cols() + 1);
            xn << x, scores[b].column;
            x = xn;
            pool.erase(pool.begin() + best);
        }
        // Backward re-test: each added term with all the others in the model and the model's own
        // residuals as the noise; the weakest below min_z2 is removed, and so on.
        for (;;) {
            const LsFit f = FitLs(x, c.y, c.segment, c.hac_lag);
            if (!f.ok || terms.size() == o.offset_terms.size()) break;
            size_t weakest = 0;
            double weakest_z2 = INFINITY;
            for (size_t k = o.offset_terms.size(); k < terms.size(); ++k) {
                const auto i = static_cast<Index>(k);
                const double z2 = f.coeffs[i] * f.coeffs[i] / f.covariance(i, i);
                if (z2 < weakest_z2) weakest_z2 = z2, weakest = k;
            }
            if (weakest_z2 > o.min_z2) break;
            const std::string effect = added_effects[weakest - o.offset_terms.size()];
            std::string others;
            for (const std::string& e : added_effects)
                if (e != effect) others += (others.empty() ? "" : ", ") + e;
            CandidateResult& r = last[effect];
            r.decision = Decision::kRejected;
            r.z2 = weakest_z2;
            r.note =
                "removed on re-test with " + others + " in the model (z2 " + Fmt(weakest_z2) + ")";
            terms.erase(terms.begin() + static_cast<long>(weakest));
            added_effects.erase(added_effects.begin() +
                                static_cast<long>(weakest - o.offset_terms.size()));
            MatrixXd xn(x.rows(), x.cols() - 1);
            const auto w = static_cast<Index>(weakest);
            xn << x.leftCols(w), x.rightCols(x.cols() - w - 1);
            x = xn;
        }
        for (auto& [effect, r] : last) cands_out.push_back(r);

        // The extended model on all bins.
        const LsFit ext = FitLs(x, c.y, c.segment, c.hac_lag);
        if (ext.ok) {
            res.extended_offset = BinModel(terms, t0, bins, ext);
            res.residual_all_extended_rms_v = std::sqrt(ext.rss / bins.size());
            if (!added_effects.empty() && std::isfinite(floor.offset_rms_v) &&
                !floor.from_standard_errors) {
                // The floor without the added effects' own variation inside the plateau windows.
                const std::vector<double> resid(ext.residuals.data(),
                                                ext.residuals.data() + ext.residuals.size());
                const Floor f2 = NoiseFloor(run, bins, o.bins.bin_s, &resid);
                if (std::isfinite(f2.offset_rms_v)) res.floor_offset_rms_v = f2.offset_rms_v;
            }
            for (size_t k = o.offset_terms.size(); k < terms.size(); ++k) {
                const auto i = static_cast<Index>(k);
                AddedEffect a;
                a.effect = added_effects[k - o.offset_terms.size()];
                a.term = terms[k];
                for (const Candidate& cand : OffsetCandidates(run, bins, o))
                    if (cand.effect == a.effect) a.unit = cand.unit;
                a.coefficient = ext.coeffs[i];
                a.stderr_ = std::sqrt(ext.covariance(i, i));
                res.added.push_back(a);
            }
        } else {
            res.could_not_test.push_back("extended model: " + ext.why);
        }

        // Before/after on the held-out stretch; models fitted on the data before it.
        const auto n = static_cast<int>(bins.size());
        const int hold = static_cast<int>(std::floor(n * (1.0 - o.holdout_fraction)));
        const int train_end = std::max(0, hold - c.cv_guard);
        std::vector<Bin> train(bins.begin(), bins.begin() + train_end),
            held(bins.begin() + hold, bins.end());
        res.n_holdout_bins = static_cast<int>(held.size());
        res.holdout_start_utime = bins[static_cast<size_t>(hold)].start_utime;
        res.train_end_utime = train.empty() ? 0 : train.back().end_utime;
        std::string why_b;
        const auto before = DeclaredOffset(
            PlateauPoints(run.plateaus, bins[static_cast<size_t>(hold)].start_utime), o, &why_b);
        if (before) {
            res.holdout_before_offset = before;
            ErrorsOn(held, model::Evaluator(*before), sens, period_s, run.first_sample_utime,
                     &res.error_before);
        } else {
            res.could_not_test.push_back(
                "error before on the held-out stretch: plateaus before it: " + why_b);
        }
        if (added_effects.empty()) {
            res.error_after = res.error_before;
            res.holdout_after_offset = res.holdout_before_offset;
        } else {
            std::vector<int> seg;
            VectorXd yt(train_end);
            for (int i = 0; i < train_end; ++i) {
                seg.push_back(bins[static_cast<size_t>(i)].segment);
                yt[i] = bins[static_cast<size_t>(i)].gyro_v;
            }
            const LsFit ft = FitLs(x.topRows(train_end), yt, seg, 0);
            if (ft.ok) {
                res.holdout_after_offset = BinModel(terms, t0, train, ft);
                ErrorsOn(held, model::Evaluator(*res.holdout_after_offset), sens, period_s,
                         run.first_sample_utime, &res.error_after);
            } else {
                res.could_not_test.push_back(
                    "error after on the held-out stretch: the data before it cannot "
                    "fit the extended model (" +
                    ft.why + ")");
            }
        }
    }
    cands_out.push_back(so.candidate);
    if (so.candidate.decision == Decision::kNotTested && so.problem.empty())
        res.could_not_test.push_back("sf_asymmetry: " + so.candidate.note);
    if (so.added) {
        res.added.push_back(*so.added);
        added_effects.push_back("sf_asymmetry");
    }
    res.candidates = cands_out;

    if (std::isfinite(res.floor_offset_rms_v) && sens) {
        double sum_inv = 0;
        int k = 0;
        for (const Bin& b : bins) {
            if (b.plateau < 0) continue;
            model::ModelInputs in = b.Inputs(run.first_sample_utime);
            sum_inv += 1.0 / sens->Value(in, model::RangePolicy::kClip);
            ++k;
        }
        if (k == 0) {
            for (const PlateauInput& p : run.plateaus) {
                model::ModelInputs in;
                in.temp_c = p.temp_mean_c;
                sum_inv += 1.0 / sens->Value(in, model::RangePolicy::kClip);
                ++k;
            }
        }
        if (k > 0) res.floor_rate_rms_dps = res.floor_offset_rms_v * sum_inv / k;
        if (res.n_holdout_bins > 0)
            res.floor_drift_dph = res.floor_rate_rms_dps * 3600.0 / std::sqrt(res.n_holdout_bins);
    }

    std::string list;
    for (const std::string& e : added_effects) list += (list.empty() ? "" : ", ") + e;
    if (static_cast<int>(bins.size()) < min_bins && !so.added)
        res.verdict = "not analysed: too few still bins (" + std::to_string(bins.size()) + ")";
    else if (!added_effects.empty())
        res.verdict =
            std::string(added_effects.size() > 1 ? "missing effects: " : "missing effect: ") + list;
    else
        res.verdict = "no missing effect";
    if (!ambiguous.empty()) {
        std::string a;
        for (const std::string& s : ambiguous) a += (a.empty() ? "" : ", ") + s;
        res.verdict += "; ambiguous: " + a;
    }
    return res;
}

std::optional<model::CoeffSet> ExtendedCoeffSet(const SensorResult& r, const std::string& run_id,
                                                const std::string& analysis_id, int64_t utime) {
    if (!r.extended_offset || !r.extended_sensitivity) return std::nullopt;
    model::CoeffSet set;
    set.utime = utime;
    set.coeff_set_id = utime;
    set.sensor_id = r.sensor_id;
    set.run_id = run_id;
    set.source = "analysis:" + analysis_id;
    set.offset = *r.extended_offset;
    set.sensitivity = *r.extended_sensitivity;
    return set;
}

}  // namespace gyrocal::analysis
