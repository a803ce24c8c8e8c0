#include "processors/analysis/analyze.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/candidates.hpp"
#include "processors/analysis/evidence.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/analysis/outcome.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/residual.hpp"
#include "processors/analysis/selection.hpp"
#include "processors/analysis/sensitivity.hpp"
#include "processors/analysis/steps.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace detail;

namespace {

// temp_knot, a last-resort shape, is not one more candidate here (offset_step.cpp).
constexpr const char* kOffsetEffects[] = {"temp_rate", "hysteresis", "temp_cubic", "supply",
                                          "warmup"};

void Notes(const SensorRun& run, const BinnedRun& binned, SensorResult& res) {
    if (!run.has_encoder)
        res.notes.push_back(
            "no encoder readings: table motion could not be excluded, every sample counted as "
            "still" +
            (run.sensitivities.empty()
                 ? std::string()
                 : " (the run recorded " + std::to_string(run.sensitivities.size()) +
                       " rotations: their turns are in the still data)"));
    if (run.n_bad_encoder > 0)
        res.notes.push_back(std::to_string(run.n_bad_encoder) +
                            " encoder readings with a time not after the previous reading's or "
                            "no counts per revolution (excluded)");
    if (run.motion_unknown)
        res.notes.push_back(
            "table motion unknown (encoder readings recorded, fewer than 2 "
            "usable): only bins inside plateau windows kept, " +
            std::to_string(binned.unknown_motion().bins) + " bins holding " +
            std::to_string(binned.unknown_motion().samples) + " samples outside them left out");
    if (binned.underfilled().bins > 0)
        res.notes.push_back(std::to_string(binned.underfilled().bins) +
                            " bins at rest below the fill limit (gaps, the run's ends) left out, "
                            "holding " +
                            std::to_string(binned.underfilled().samples) + " samples");
    if (run.n_seq_gaps > 0)
        res.notes.push_back(std::to_string(run.n_seq_gaps) +
                            " samples missing by sequence number (bins with gaps dropped)");
    if (run.n_bad_air > 0)
        res.notes.push_back(std::to_string(run.n_bad_air) +
                            " chamber air readings non-finite or repeated in time (excluded)");
    if (run.n_bad_samples > 0)
        res.notes.push_back(std::to_string(run.n_bad_samples) +
                            " samples non-finite or out of order (excluded)");
    if (!binned.bins().empty() && binned.bins().back().segment > 0)
        res.notes.push_back("still data in " + std::to_string(binned.bins().back().segment + 1) +
                            " contiguous stretches (moves and gaps split it)");
    res.power_on_source = run.power_on_source;
    if (run.power_on_assumed)
        res.notes.push_back(
            "time since power-on counted from the unit's first sample (no "
            "power-on record): warm-up terms assume the unit was powered then");
}

// The sensitivity side (sensitivity.hpp): its figures into res; the outcome for the candidate.
SensitivityOutcome Sensitivity(const SensorRun& run, const AnalysisOptions& o, SensorResult& res) {
    SensitivityOutcome so = AnalyzeSensitivity(run.sensitivities, o);
    res.n_sensitivity_points = so.n_points;
    res.declared_sensitivity = so.declared;
    res.extended_sensitivity = so.extended;
    res.sens_rel_rms_before = so.rel_rms_before;
    res.sens_rel_rms_after = so.rel_rms_after;
    res.sens_chi2_dof_before = so.chi2_dof_before;
    res.sens_chi2_dof_after = so.chi2_dof_after;
    if (!so.problem.empty())
        res.could_not_test.push_back("rates in deg/s and sf_asymmetry: " + so.problem);
    return so;
}

// T0 of every offset model: mid-range rounded to 5 degC, as the fitter does.
double OffsetT0(const std::vector<Bin>& bins) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Bin& b : bins) lo = std::min(lo, b.temp_c), hi = std::max(hi, b.temp_c);
    return bins.empty() ? 25.0 : RoundT0(lo, hi);
}

void Floors(const BinnedRun& binned, const Split& split, SensorResult& res) {
    if (!std::isfinite(res.floor_offset_rms_v) || !res.declared_sensitivity) return;
    const double inv_s =
        MeanInverseSensitivity(binned, *res.declared_sensitivity, AllRows(binned.size()));
    if (!std::isfinite(inv_s)) return;
    res.floor_rate_rms_dps = res.floor_offset_rms_v * inv_s;
    if (split.n_blocks > 0 && !split.held.empty()) {
        const double bins_per_block = static_cast<double>(split.held.size()) / split.n_blocks;
        res.floor_drift_dph = res.floor_rate_rms_dps * 3600.0 / std::sqrt(bins_per_block);
    }
}

// Steps 8 and 9's evidence on the final model: the run's noise measured on its residual (the k of
// the floor bound unless the option sets it), the generic features and the windows judged against
// surrogates of that noise, the residual's diagnostics.
void Residue(const BinnedRun& binned, const Split& split, double t0, const AnalysisOptions& o,
             SensorResult& res) {
    const std::vector<std::string>& terms = res.extended_offset->term_names;
    const Context train = MakeContext(binned, split.train, t0, o);
    const MatrixXd base = binned.Design(terms, t0);
    res.floor_prediction_rms_v =
        res.floor_offset_rms_v *
        std::sqrt(MeanLeverage(train.Design(terms), base(split.held, Eigen::all)));
    const VectorXd r_all = Residuals(binned, *res.extended_offset, AllRows(binned.size()));
    const Surrogates s = MakeSurrogates(binned, r_all, o);
    res.slow_noise_measured = s.model.measured && o.slow_noise_floor_ratio < 0;
    res.slow_noise_k = o.slow_noise_floor_ratio >= 0 ? o.slow_noise_floor_ratio : s.model.k;
    res.noise_note = o.slow_noise_floor_ratio >= 0 ? "k set by the option" : s.model.note;
    res.n_surrogates = static_cast<int>(s.noise.size());
    std::vector<Family> families = FeatureFamilies(binned, train, base, o, &res.absent_channels);
    for (Family& f : NamedShapeFamilies(binned, train, base, *res.extended_offset, res.added))
        families.push_back(std::move(f));
    res.features = JudgeFeatures(binned, train, split, base, r_all, res.floor_offset_rms_v,
                                 families, s.noise, o, &res.feature_null_threshold);
    TransferCheck(base, terms, s.noise, o, res);
    res.windows_above = WindowsAbove(binned, base, s, o, &res.window_null_threshold);
    res.residual = Diagnose(binned, r_all, res.floor_offset_rms_v, o);
    AngleConfound(res);
}

// The offset side of one pass (steps 4-9): chosen terms, extended model, evidence.
void OffsetPass(const BinnedRun& binned, const Split& split, double t0, const AnalysisOptions& o,
                const MatrixXd& nuisance, SensorResult& res) {
    const Selection sel = OffsetStep(binned, split, t0, o, nuisance, res);
    FinalModels(binned, sel.terms, t0, o, nuisance, res);
    Floors(binned, split, res);
    if (res.extended_offset) Residue(binned, split, t0, o, res);
}

// The strongest time-shaped generic feature that explains held-out data, centred on all bins (so
// that the intercept of a model fitted with it is the run's mean): the nuisance of the joint
// search. 0 columns when none does.
MatrixXd StrongTimeShape(const BinnedRun& binned, const Split& split, double t0,
                         const AnalysisOptions& o, const SensorResult& res, std::string& name) {
    // A nuisance must be of the size a candidate needs (min_effect_floor_ratio): a flag may be
    // smaller (min_feature_floor_ratio), a shape that moves the candidates' search may not.
    const FeatureResult* top = nullptr;
    for (const FeatureResult& f : res.features)
        if (f.explains_heldout && !top &&
            (f.channel == "time" || f.channel == "time since power-on") &&
            !(f.effect_rms_v <= o.min_effect_floor_ratio * res.floor_offset_rms_v))
            top = &f;
    if (!top || !res.extended_offset) return MatrixXd(static_cast<Index>(binned.size()), 0);
    const Context train = MakeContext(binned, split.train, t0, o);
    for (const GenericFeature& g :
         GenericFeatures(binned, train, binned.Design(res.extended_offset->term_names, t0), o)) {
        if (g.name != top->feature || g.channel != top->channel) continue;
        name = g.name + " [" + g.channel + "; " + g.detail + "]";
        return g.columns.rowwise() - g.columns.colwise().mean();
    }
    return MatrixXd(static_cast<Index>(binned.size()), 0);
}

std::vector<std::string> AddedNames(const SensorResult& r) {
    std::vector<std::string> v;
    for (const AddedEffect& a : r.added) v.push_back(a.effect);
    std::sort(v.begin(), v.end());
    return v;
}

// Joint search (step 8): when a time-shaped feature explains held-out data, the candidates are
// tested again with it accounted for (nuisance columns, fitted with the terms, never kept in the
// model). That pass is the answer: what it names was masked by the time shape (named now), and
// what only the first pass named mimicked the time shape (the shape explained held-out data with
// it in, it adds nothing with the shape in): not attributed, with what would separate the two.
void JointSearch(const BinnedRun& binned, const Split& split, double t0, const AnalysisOptions& o,
                 const SensorResult& before, SensorResult& res) {
    std::string name;
    const MatrixXd nuisance = StrongTimeShape(binned, split, t0, o, res, name);
    if (nuisance.cols() == 0) return;
    SensorResult joint = before;
    OffsetPass(binned, split, t0, o, nuisance, joint);
    const std::vector<std::string> a = AddedNames(res), b = AddedNames(joint);
    if (a == b) return;  // the same terms: the first pass stands (its figures without nuisance)
    joint.notes.push_back("joint search: the candidates tested again with " + name +
                          " accounted for (it explains held-out data; fitted with them, not kept "
                          "in the model)");
    for (const std::string& e : a) {
        if (std::find(b.begin(), b.end(), e) != b.end()) continue;
        const std::string why =
            e + " (named only while " + name + " is not accounted for: with it in the model " + e +
            " adds nothing, and it explained held-out data with " + e +
            " in; to separate: " + SeparationFromTime(e, name.substr(0, name.find(" ["))) + ")";
        joint.not_attributed.push_back(why);
        // The row shows the term the first pass named (its shape parameter and edge flag), the
        // one the verdict is about, not what the second pass made of the candidate.
        const auto first = std::find_if(res.candidates.begin(), res.candidates.end(),
                                        [&](const CandidateResult& c) { return c.effect == e; });
        for (CandidateResult& c : joint.candidates) {
            if (c.effect != e) continue;
            if (first != res.candidates.end()) c = *first;
            c.decision = Decision::kRejected, c.note = "not attributed: " + why;
        }
    }
    res = std::move(joint);
}

}  // namespace

// ---- hook (issue 29, loop): the analysis of bins made elsewhere (bins_incremental.hpp) ----
SensorResult Analyze(const SensorRun& run, const AnalysisOptions& o) {
    if (const std::string p = o.Validate(); !p.empty())
        throw std::invalid_argument("analysis options: " + p);
    return AnalyzeBinned(run, BinnedRun(run, o.bins), o);
}

SensorResult AnalyzeBinned(const SensorRun& run, const BinnedRun& binned,
                           const AnalysisOptions& o) {
    if (const std::string p = o.Validate(); !p.empty())
        throw std::invalid_argument("analysis options: " + p);
    if (binned.bin_s() != o.bins.bin_s)
        throw std::invalid_argument("analysis options: bins of " + text::Sig(binned.bin_s(), 3) +
                                    " s given, bin_s is " + text::Sig(o.bins.bin_s, 3) + " s");
    // ---- end of hook ----
    SensorResult res;
    res.sensor_id = run.sensor_id;
    res.bin_s = o.bins.bin_s;
    res.n_plateaus = static_cast<int>(run.plateaus.size());
    res.claimed_false_positive_rate = o.ClaimedFalsePositiveRate();
    res.n_bins = static_cast<int>(binned.size());
    Notes(run, binned, res);
    const SensitivityOutcome so = Sensitivity(run, o, res);
    const double t0 = OffsetT0(binned.bins());
    const Split split = MakeSplit(binned.bins(), o);
    res.n_holdout_bins = static_cast<int>(split.held.size());
    res.n_holdout_blocks = split.n_blocks;
    res.n_train_bins = static_cast<int>(split.train.size());
    for (Index i : split.held) res.holdout_bins.push_back(static_cast<int>(i));
    const int min_bins = 3 * o.cv_blocks + 10;
    const bool analysed = res.n_train_bins >= min_bins && split.n_blocks > 0;
    const MatrixXd none(static_cast<Index>(binned.size()), 0);
    if (!analysed) {
        res.could_not_test.push_back("offset candidates: " + std::to_string(res.n_train_bins) +
                                     " training bins of " + text::Sig(o.bins.bin_s, 3) + " s and " +
                                     std::to_string(split.n_blocks) + " held-out blocks, need " +
                                     std::to_string(min_bins) + " and 1");
        for (const char* e : kOffsetEffects)
            res.candidates.push_back(
                {e, "", Decision::kNotTested, kNan, kNan, 0, "too few still bins", kNan, false});
        FinalModels(binned, o.offset_terms, t0, o, none, res);
        Floors(binned, split, res);
    } else {
        const SensorResult before = res;
        OffsetPass(binned, split, t0, o, none, res);
        JointSearch(binned, split, t0, o, before, res);
    }
    res.candidates.push_back(so.candidate);
    if (so.candidate.decision == Decision::kNotTested && so.problem.empty())
        res.could_not_test.push_back("sf_asymmetry: " + so.candidate.note);
    if (so.added) res.added.push_back(*so.added);
    AngleConfound(res);  // again: sf_asymmetry is added only now (Residue ran before)
    Edges(binned, o, res);
    Conclude(analysed, o, res);
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
