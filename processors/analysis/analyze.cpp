#include "analyze.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#include "candidates.hpp"
#include "heldout.hpp"
#include "outcome.hpp"
#include "regress.hpp"
#include "residual.hpp"
#include "score.hpp"
#include "selection.hpp"
#include "sensitivity.hpp"
#include "text/number.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace detail;

namespace {

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
        res.notes.push_back("time since power-on counted from the unit's first sample (no "
                            "power-on record): warm-up terms assume the unit was powered then");
}

std::vector<Index> AllRows(size_t n) {
    std::vector<Index> rows(n);
    for (size_t i = 0; i < n; ++i) rows[i] = static_cast<Index>(i);
    return rows;
}

// T0 of every offset model: mid-range rounded to 5 degC, as the fitter does.
double OffsetT0(const std::vector<Bin>& bins) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Bin& b : bins) lo = std::min(lo, b.temp_c), hi = std::max(hi, b.temp_c);
    return bins.empty() ? 25.0 : RoundT0(lo, hi);
}

// The floor of the declared model's residual on all bins (fitted on the training bins).
Floor DeclaredFloor(const Context& train, const BinnedRun& binned, const AnalysisOptions& o) {
    const LsFit f = FitLs(train.Design(o.offset_terms), train.y, train.segment, 0);
    if (!f.ok) return {};
    VectorXd y(static_cast<Index>(binned.size()));
    for (size_t i = 0; i < binned.size(); ++i) y[static_cast<Index>(i)] = binned.bins()[i].gyro_v;
    return NoiseFloor(binned.bins(), y - binned.Design(o.offset_terms, train.t0) * f.coeffs);
}

// Step 4: the candidates' choice on the training bins.
Selection Choose(const Context& train, const BinnedRun& binned, const AnalysisOptions& o,
                 SensorResult& res, const Floor& floor) {
    std::vector<Candidate> pool;
    for (const Candidate& cand : OffsetCandidates(binned, o)) {
        if (cand.why_not.empty()) {
            pool.push_back(cand);
            continue;
        }
        CandidateResult r;
        r.effect = cand.effect;
        r.note = cand.why_not;
        res.candidates.push_back(r);
        res.could_not_test.push_back(cand.effect + ": " + cand.why_not);
    }
    Selection sel = SelectOffsetTerms(train, std::move(pool), floor, o);
    for (const CandidateResult& r : sel.candidates) res.candidates.push_back(r);
    return sel;
}

struct HeldOut {
    bool confirmed = false;
};

// One model of the held-out check (design x of `terms` on the training bins): fitted on the
// training bins into `model`, judged on the held-out bins into `errors`. Returns the fit and its
// held-out residual [V], or nullopt with the reason in could_not_test ("<what> on the held-out
// bins: ...").
struct Judged {
    LsFit fit;
    VectorXd residual_v;
};
std::optional<Judged> FitAndJudge(const Context& train, const BinnedRun& binned, const Split& split,
                                  const std::vector<std::string>& terms, const MatrixXd& x,
                                  const std::string& what, std::optional<model::Model>& model,
                                  ErrorFigures& errors, SensorResult& res) {
    LsFit f = FitLs(x, train.y, train.segment, train.hac_lag);
    if (!f.ok) {
        res.could_not_test.push_back(what + " on the held-out bins: " + f.why);
        return std::nullopt;
    }
    model = FitModel(terms, train.t0, binned, train.rows, f);
    VectorXd r = Residuals(binned, *model, split.held);
    errors = ErrorsOn(binned, r, split.held, split.held_block, res.declared_sensitivity);
    return Judged{std::move(f), std::move(r)};
}

// Step 5: declared and chosen terms fitted on the training bins, judged on the held-out bins.
HeldOut Confirm(const Context& train, const BinnedRun& binned, const Split& split,
                const Selection& sel, const AnalysisOptions& o, SensorResult& res) {
    HeldOut h;
    const std::optional<model::Model>& sens = res.declared_sensitivity;
    const std::optional<Judged> before =
        FitAndJudge(train, binned, split, o.offset_terms, train.Design(o.offset_terms),
                    "error before", res.holdout_before_offset, res.error_before, res);
    if (!before) return h;
    const double inv_s = sens ? MeanInverseSensitivity(binned, *sens, split.held) : kNan;
    if (sel.terms.size() == o.offset_terms.size()) {
        res.error_after = res.error_before;
        res.holdout_after_offset = res.holdout_before_offset;
        ExpectedAfter(before->fit, binned.Design(o.offset_terms, train.t0)(split.held, Eigen::all),
                      inv_s, &res);
        res.heldout_gain_v2 = res.heldout_slope = res.heldout_gain_z = kNan;
        return h;
    }
    const std::optional<Judged> after =
        FitAndJudge(train, binned, split, sel.terms, sel.x, "error after", res.holdout_after_offset,
                    res.error_after, res);
    if (!after) return h;
    const Gain g =
        HeldOutGain(before->residual_v, after->residual_v, split.held_block, train.hac_lag);
    res.heldout_gain_v2 = g.mean_v2;
    res.heldout_slope = g.slope;
    res.heldout_gain_z = g.z;
    ExpectedAfter(after->fit, binned.Design(sel.terms, train.t0)(split.held, Eigen::all), inv_s,
                  &res);
    // Beyond its noise (z) and never at the cost of the held-out drift.
    const bool drift_ok = !std::isfinite(res.error_before.drift_dph) ||
                          !std::isfinite(res.error_after.drift_dph) ||
                          res.error_after.drift_dph <= res.error_before.drift_dph;
    h.confirmed = std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0 && drift_ok;
    if (std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0 && !drift_ok)
        res.notes.push_back("the chosen terms lowered the held-out RMS but raised the held-out "
                            "drift (" + text::Sig(res.error_before.drift_dph, 3) + " -> " +
                            text::Sig(res.error_after.drift_dph, 3) + " deg/h): not added");
    return h;
}

// Step 6 and the figures on all bins: declared and extended models, the floor.
void FinalModels(const BinnedRun& binned, const std::vector<std::string>& terms, double t0,
                 const AnalysisOptions& o, SensorResult& res) {
    const Context all = MakeContext(binned, AllRows(binned.size()), t0, o);
    const LsFit fd = FitLs(all.Design(o.offset_terms), all.y, all.segment, all.hac_lag);
    if (fd.ok) {
        res.declared_offset = FitModel(o.offset_terms, t0, binned, all.rows, fd);
        res.residual_all_rms_v = std::sqrt(fd.rss / static_cast<double>(binned.size()));
    } else {
        res.could_not_test.push_back("declared offset model on all bins: " + fd.why);
    }
    const MatrixXd x = all.Design(terms);
    const LsFit fe = FitLs(x, all.y, all.segment, all.hac_lag);
    if (!fe.ok) {
        res.could_not_test.push_back("extended model: " + fe.why);
        return;
    }
    res.extended_offset = FitModel(terms, t0, binned, all.rows, fe);
    res.residual_all_extended_rms_v = std::sqrt(fe.rss / static_cast<double>(binned.size()));
    res.floor_offset_rms_v = NoiseFloor(binned.bins(), fe.residuals).offset_rms_v;
    for (size_t k = o.offset_terms.size(); k < terms.size(); ++k) {
        const auto i = static_cast<Index>(k);
        for (AddedEffect& a : res.added)
            if (a.term == terms[k]) a.coefficient = fe.coeffs[i], a.stderr_ = std::sqrt(fe.covariance(i, i));
    }
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

// Step 8's guard, an encompassing test on the held-out bins between each added term and each
// time-shaped generic feature (drift, slow transient, step, periodic; its parameter chosen on the
// training bins): with both in the model, a real effect keeps improving the held-out error beyond
// its noise while its mimic does not, and a term that only mimicked the feature stops improving
// it while the feature still explains held-out data (the features' own standard: z above
// gate_min_z and min_feature_drop of the squared residual). Such a term is taken out of the
// selection ("not attributed"). Comparing each ALONE would refuse a real effect whenever a
// feature, fitted to the same held-out residual, also takes in the noise or a second effect.
std::vector<std::string> Displace(const Context& train, const BinnedRun& binned,
                                  const Split& split, Selection& sel, const AnalysisOptions& o,
                                  SensorResult& res) {
    std::vector<std::string> out;
    const size_t nd = o.offset_terms.size();
    const MatrixXd none(static_cast<Index>(binned.size()), 0);
    const MatrixXd all_terms = binned.Design(sel.terms, train.t0);
    const VectorXd r_named = HeldResidual(binned, train, split, all_terms, none);
    if (sel.terms.size() == nd || r_named.size() == 0) return out;
    const std::vector<GenericFeature> features =
        GenericFeatures(binned, train, binned.Design(o.offset_terms, train.t0), o);
    const std::vector<Candidate> cands = OffsetCandidates(binned, o);
    auto improves = [&](const Gain& g) {
        return std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0;
    };
    for (size_t k = nd; k < sel.terms.size(); ++k) {
        bool edge = false;
        for (const Candidate& c : cands)
            edge = edge || (c.effect == "warmup" && c.grid.size() >= 2 &&
                            sel.added_effects[k - nd] == c.effect && sel.terms[k] == c.grid.back());
        std::vector<std::string> without = sel.terms;
        without.erase(without.begin() + static_cast<long>(k));
        const MatrixXd base = binned.Design(without, train.t0);
        for (const GenericFeature& f : features) {
            if (!f.competes) continue;
            const VectorXd r_feature = HeldResidual(binned, train, split, base, f.columns);
            const VectorXd r_both = HeldResidual(binned, train, split, all_terms, f.columns);
            if (r_feature.size() != r_named.size() || r_both.size() != r_named.size()) continue;
            const Gain term_given_feature =
                HeldOutGain(r_feature, r_both, split.held_block, train.hac_lag);
            const Gain feature_given_term =
                HeldOutGain(r_named, r_both, split.held_block, train.hac_lag);
            const double feature_drop = 1.0 - r_both.squaredNorm() / r_named.squaredNorm();
            const bool mimic = !improves(term_given_feature) && improves(feature_given_term) &&
                               feature_drop > o.min_feature_drop;
            // A warm-up whose tau sits at the upper end of its grid is not a shape the data
            // resolved (the best tau may lie beyond it): a time-shaped feature that predicts its
            // held-out residual at least as well takes it.
            const double drop_alone = 1.0 - r_feature.squaredNorm() / r_named.squaredNorm();
            const bool tie_at_edge = edge && std::isfinite(drop_alone) && drop_alone >= 0.0;
            if (!mimic && !tie_at_edge) continue;
            const std::string& effect = sel.added_effects[k - nd];
            const std::string why =
                mimic ? "explains its held-out residual with the term in the model (z " +
                            text::Sig(feature_given_term.z, 3) + "), the term none with it in (z " +
                            text::Sig(term_given_feature.z, 3) + ")"
                      : "explains its held-out residual better: z " +
                            text::Sig(HeldOutGain(r_named, r_feature, split.held_block, train.hac_lag).z, 3);
            res.not_attributed.push_back(effect + " (" + f.name + ", " + f.detail + ", " + why +
                                         ")");
            out.push_back(effect);
            break;
        }
    }
    for (size_t j = 0; j < out.size(); ++j) {
        const std::string& effect = out[j];
        const auto it = std::find(sel.added_effects.begin(), sel.added_effects.end(), effect);
        sel.terms.erase(sel.terms.begin() + static_cast<long>(nd) + (it - sel.added_effects.begin()));
        sel.added_effects.erase(it);
        for (CandidateResult& c : res.candidates)
            if (c.effect == effect)
                c.decision = Decision::kRejected,
                c.note = "not attributed: " + res.not_attributed[j];
    }
    if (!out.empty()) sel.x = train.Design(sel.terms);
    return out;
}

// What became of each collinear pair added whole, in its "a vs b" entry of the verdict's
// ambiguities: both kept (the pair predicts unseen data; which of the two carries the effect the
// data cannot say), one of them not attributed (a generic feature explained its part better), or
// neither (the held-out check refused the chosen terms).
void JointPairFates(Selection& sel, bool confirmed, const SensorResult& res) {
    auto added = [&](const std::string& e) {
        for (const AddedEffect& a : res.added)
            if (a.effect == e) return true;
        return false;
    };
    for (const Selection::JointPair& p : sel.joint_pairs) {
        std::string& entry = sel.ambiguous[p.ambiguous_index];
        if (!confirmed)
            entry += " (chosen together, not confirmed on the held-out data)";
        else if (added(p.a) && added(p.b))
            entry += " (both kept: together they predict data they did not see)";
        else if (added(p.a) != added(p.b))
            entry += " (" + (added(p.a) ? p.a : p.b) + " kept; " + (added(p.a) ? p.b : p.a) +
                     " not attributed)";
    }
}

// Steps 4, 5 and 8's guard: the offset terms chosen, confirmed on the held-out bins and not
// displaced by a generic feature.
Selection OffsetStep(const BinnedRun& binned, const Split& split, double t0,
                     const AnalysisOptions& o, SensorResult& res) {
    const Context train = MakeContext(binned, split.train, t0, o);
    Selection sel = Choose(train, binned, o, res, DeclaredFloor(train, binned, o));
    HeldOut h = Confirm(train, binned, split, sel, o, res);
    if (h.confirmed && !Displace(train, binned, split, sel, o, res).empty())
        h = Confirm(train, binned, split, sel, o, res);
    for (size_t k = o.offset_terms.size(); k < sel.terms.size(); ++k) {
        const std::string& effect = sel.added_effects[k - o.offset_terms.size()];
        if (h.confirmed) {
            AddedEffect a;
            a.effect = effect;
            a.term = sel.terms[k];
            for (const Candidate& c : OffsetCandidates(binned, o))
                if (c.effect == effect) a.unit = c.unit;
            res.added.push_back(a);
        } else {
            res.unconfirmed.push_back(effect);
        }
    }
    if (!h.confirmed) sel.terms = o.offset_terms;
    JointPairFates(sel, h.confirmed, res);
    for (CandidateResult& c : res.candidates)
        if (c.decision == Decision::kAdded && !h.confirmed) {
            c.decision = Decision::kRejected;
            c.note = "chosen on the training bins, not confirmed on the held-out bins "
                     "(prediction slope " + text::Sig(res.heldout_slope, 3) + ", " +
                     text::Sig(res.heldout_gain_z, 3) + " standard errors, need " +
                     text::Sig(o.gate_min_z, 3) + "; squared error change " +
                     text::Sig(-res.heldout_gain_v2, 3) + " V^2)";
        }
    return sel;
}

// The number a searched term names: "warmup(312)" -> 312; NaN when it names none.
double ParamOf(const std::string& term) {
    const size_t open = term.find('(');
    if (open == std::string::npos) return kNan;
    char* end = nullptr;
    const double v = std::strtod(term.c_str() + open + 1, &end);
    return end && *end == ')' ? v : kNan;
}

// Shape parameters at an end of their searched range (item 2 of step 4's search; the generic
// features' own in residual.cpp): on every candidate, and listed in `edges` for those chosen on
// the training bins and the features that explain held-out data.
void Edges(const BinnedRun& binned, const AnalysisOptions& o, SensorResult& res) {
    const std::vector<Candidate> cands = OffsetCandidates(binned, o);
    for (CandidateResult& c : res.candidates) {
        if (!c.grid_edge || c.term.empty()) continue;
        for (const Candidate& k : cands) {
            if (k.effect != c.effect || k.grid.size() < 2) continue;
            const bool upper = c.term == k.grid.back();
            const double lo = ParamOf(k.grid.front()), hi = ParamOf(k.grid.back());
            const char* param = c.effect == "temp_rate"    ? "dT/dt time constant"
                                : c.effect == "hysteresis" ? "branch width"
                                                           : "tau";
            const char* unit = c.effect == "hysteresis" ? " degC" : " s";
            c.edge = EdgeText(param, upper, lo, hi, unit);
        }
        const bool chosen = c.decision == Decision::kAdded || c.decision == Decision::kAmbiguous ||
                            c.note.rfind("not attributed", 0) == 0 ||
                            std::find(res.unconfirmed.begin(), res.unconfirmed.end(), c.effect) !=
                                res.unconfirmed.end();
        if (chosen && !c.edge.empty()) res.edges.push_back(c.effect + ": " + c.edge);
    }
    for (const FeatureResult& f : res.features)
        if (f.explains_heldout && !f.edge.empty())
            res.edges.push_back(f.feature + " [" + f.channel + "]: " + f.edge);
}

// A null that depends on the table angle (a generic feature of the encoder's angle explains
// held-out data) biases every turn: the rotation integral takes in the null's change between the
// turn's start and end angles, with a sign that follows the turn's direction, which is the
// signature of sf_asymmetry. The direction term is then not attributed (and not applied): turns
// in both directions from the same angle would separate the two.
void AngleConfound(SensorResult& res) {
    const FeatureResult* angle = nullptr;
    for (const FeatureResult& f : res.features)
        if (f.explains_heldout && f.channel.rfind("encoder: table angle", 0) == 0) angle = &f;
    const auto it = std::find_if(res.added.begin(), res.added.end(),
                                 [](const AddedEffect& a) { return a.effect == "sf_asymmetry"; });
    if (angle == nullptr || it == res.added.end()) return;
    res.added.erase(it);
    res.extended_sensitivity = res.declared_sensitivity;  // as when the term is not added
    res.sens_rel_rms_after = res.sens_rel_rms_before;
    res.sens_chi2_dof_after = res.sens_chi2_dof_before;
    const std::string why = "sf_asymmetry (the null depends on the table angle: " + angle->feature +
                            " explains held-out data, and a turn integrates that null's change "
                            "between its start and end angles with the sign of its direction; "
                            "turns in both directions from the same angle would separate them)";
    res.not_attributed.push_back(why);
    for (CandidateResult& c : res.candidates)
        if (c.effect == "sf_asymmetry") c.decision = Decision::kRejected, c.note = "not attributed: " + why;
}

// Steps 8 and 9 on the final model: features, diagnostics, outcome.
void Residue(const BinnedRun& binned, const Split& split, double t0, bool analysed,
             const Selection& sel, const AnalysisOptions& o, SensorResult& res) {
    if (analysed && res.extended_offset) {
        const Context train = MakeContext(binned, split.train, t0, o);
        res.floor_prediction_rms_v =
            res.floor_offset_rms_v *
            std::sqrt(MeanLeverage(train.Design(sel.terms),
                                   binned.Design(sel.terms, t0)(split.held, Eigen::all)));
        const VectorXd r_all = Residuals(binned, *res.extended_offset, AllRows(binned.size()));
        const MatrixXd base = binned.Design(sel.terms, t0);
        res.features =
            JudgeFeatures(binned, train, split, base, r_all, res.floor_offset_rms_v,
                          GenericFeatures(binned, train, base, o, &res.absent_channels), o);
        res.residual = Diagnose(binned, r_all, res.floor_offset_rms_v, o);
        AngleConfound(res);
    }
    Edges(binned, o, res);
    Conclude(analysed, sel.ambiguous, o, res);
}
}  // namespace

// ---- hook (issue 29, loop): the analysis of bins made elsewhere (bins_incremental.hpp) ----
SensorResult Analyze(const SensorRun& run, const AnalysisOptions& o) {
    if (const std::string p = o.Problem(); !p.empty())
        throw std::invalid_argument("analysis options: " + p);
    return AnalyzeBinned(run, BinnedRun(run, o.bins), o);
}

SensorResult AnalyzeBinned(const SensorRun& run, const BinnedRun& binned,
                           const AnalysisOptions& o) {
    if (const std::string p = o.Problem(); !p.empty())
        throw std::invalid_argument("analysis options: " + p);
    if (binned.bin_s() != o.bins.bin_s)
        throw std::invalid_argument("analysis options: bins of " + text::Sig(binned.bin_s(), 3) +
                                    " s given, bin_s is " + text::Sig(o.bins.bin_s, 3) + " s");
    // ---- end of hook ----
    SensorResult res;
    res.sensor_id = run.sensor_id;
    res.bin_s = o.bins.bin_s;
    res.n_plateaus = static_cast<int>(run.plateaus.size());
    res.n_bins = static_cast<int>(binned.size());
    Notes(run, binned, res);

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

    const double t0 = OffsetT0(binned.bins());
    const Split split = MakeSplit(binned.bins(), o);
    res.n_holdout_bins = static_cast<int>(split.held.size());
    res.n_holdout_blocks = split.n_blocks;
    res.n_train_bins = static_cast<int>(split.train.size());
    for (Index i : split.held) res.holdout_bins.push_back(static_cast<int>(i));
    const int min_bins = 3 * o.cv_blocks + 10;
    const bool analysed = res.n_train_bins >= min_bins && split.n_blocks > 0;
    Selection sel;
    sel.terms = o.offset_terms;
    if (!analysed) {
        res.could_not_test.push_back(
            "offset candidates: " + std::to_string(res.n_train_bins) + " training bins of " +
            text::Sig(o.bins.bin_s, 3) + " s and " + std::to_string(split.n_blocks) +
            " held-out blocks, need " + std::to_string(min_bins) + " and 1");
        for (const char* e : kOffsetEffects)
            res.candidates.push_back({e, "", Decision::kNotTested, kNan, kNan, 0,
                                      "too few still bins", kNan, false});
    } else {
        sel = OffsetStep(binned, split, t0, o, res);
    }
    FinalModels(binned, sel.terms, t0, o, res);
    Floors(binned, split, res);
    res.candidates.push_back(so.candidate);
    if (so.candidate.decision == Decision::kNotTested && so.problem.empty())
        res.could_not_test.push_back("sf_asymmetry: " + so.candidate.note);
    if (so.added) res.added.push_back(*so.added);
    Residue(binned, split, t0, analysed, sel, o, res);
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
