#include "analyze.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "candidates.hpp"
#include "declared.hpp"
#include "fit/fit.hpp"
#include "regress.hpp"
#include "score.hpp"
#include "selection.hpp"
#include "sensitivity.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace detail;

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
        Selection sel = SelectOffsetTerms(c, std::move(pool), floor, o);
        terms = sel.terms;
        added_effects = sel.added_effects;
        ambiguous = sel.ambiguous;
        const MatrixXd x = sel.x;
        for (const CandidateResult& r : sel.candidates) cands_out.push_back(r);

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
            const LsFit ft = FitLs(x.topRows(train_end), yt, seg, c.hac_lag);
            if (ft.ok) {
                res.holdout_after_offset = BinModel(terms, t0, train, ft);
                ErrorsOn(held, model::Evaluator(*res.holdout_after_offset), sens, period_s,
                         run.first_sample_utime, &res.error_after);
                ExpectedAfter(ft, x.bottomRows(n - hold), held, sens, run.first_sample_utime,
                              &res);
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
        double inv_s = MeanInverseSensitivity(*sens, bins, run.first_sample_utime, true);
        if (std::isnan(inv_s) && !run.plateaus.empty()) {
            // No bin in a plateau window: at the plateau means' temperatures.
            double sum_inv = 0;
            for (const PlateauInput& p : run.plateaus) {
                model::ModelInputs in;
                in.temp_c = p.temp_mean_c;
                sum_inv += 1.0 / sens->Value(in, model::RangePolicy::kClip);
            }
            inv_s = sum_inv / static_cast<double>(run.plateaus.size());
        }
        if (std::isfinite(inv_s)) res.floor_rate_rms_dps = res.floor_offset_rms_v * inv_s;
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
