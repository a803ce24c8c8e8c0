// Steps 4-6 of the analysis (analyze.hpp, steps.hpp).
#include <algorithm>
#include <cmath>
#include <optional>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/localized.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/residual.hpp"
#include "processors/analysis/steps.hpp"
#include "processors/model/terms.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

std::vector<Index> AllRows(size_t n) {
    std::vector<Index> rows(n);
    for (size_t i = 0; i < n; ++i) rows[i] = static_cast<Index>(i);
    return rows;
}

namespace {

// The floor of the declared model's residual on all bins (fitted on the training bins).
Floor DeclaredFloor(const Context& train, const BinnedRun& binned, const AnalysisOptions& o) {
    const LsFit f = FitLs(train.Design(o.offset_terms), train.y, train.segment, 0);
    if (!f.ok) return {};
    return NoiseFloor(binned.bins(),
                      BinValues(binned) - train.AllDesign(o.offset_terms) * f.coeffs);
}

// Step 4: the candidates' choice on the training bins. The warm-up, when testable, is left to its
// localized check (localized.hpp) and returned in `warmup`.
Selection Choose(const Context& train, const BinnedRun& binned, const AnalysisOptions& o,
                 SensorResult& res, Candidate& warmup) {
    std::vector<Candidate> pool;
    for (const Candidate& cand : OffsetCandidates(binned, o)) {
        if (cand.why_not.empty()) {
            if (cand.effect == "warmup")
                warmup = cand;
            else
                pool.push_back(cand);
            continue;
        }
        res.could_not_test.push_back(cand.effect + ": " + cand.why_not);
        // A last-resort shape is not one more untested candidate (max_untested_fraction): it is
        // untestable whenever temp_cubic is, or when the data cannot place a knot, which the
        // line above says.
        // Nor is thermometer_lag: untestable exactly when temp_rate is (no ramps).
        if (cand.last_resort || cand.effect == "thermometer_lag") continue;
        CandidateResult r;
        r.effect = cand.effect;
        r.note = cand.why_not;
        res.candidates.push_back(r);
    }
    Selection sel = SelectOffsetTerms(train, std::move(pool), DeclaredFloor(train, binned, o), o);
    for (const CandidateResult& r : sel.candidates) res.candidates.push_back(r);
    return sel;
}

// One model of the held-out check, fitted on the training bins into `model` and judged on the
// held-out bins into `errors` (its own residual: the nuisance, which no model carries, is left in
// it). nullopt with the reason in could_not_test.
std::optional<LsFit> FitAndJudge(const Context& train, const BinnedRun& binned, const Split& split,
                                 const std::vector<std::string>& terms, const std::string& what,
                                 std::optional<model::Model>& model, ErrorFigures& errors,
                                 SensorResult& res) {
    LsFit f = FitLs(train.Design(terms), train.y, train.segment, train.hac_lag);
    if (!f.ok) {
        res.could_not_test.push_back(what + " on the held-out bins: " + f.why);
        return std::nullopt;
    }
    model = FitModel(terms, train.t0, binned, train.rows, f);
    errors = ErrorsOn(binned, Residuals(binned, *model, split.held), split.held, split.held_block,
                      res.declared_sensitivity);
    return f;
}

// Step 5: declared and chosen terms fitted on the training bins, judged on the held-out bins. The
// gate asks what the chosen terms add to `gate_base` (the declared terms and a warm-up its own
// check confirmed): nothing beyond it, nothing to confirm.
bool Confirm(const Context& train, const BinnedRun& binned, const Split& split,
             const Selection& sel, const std::vector<std::string>& gate_base,
             const AnalysisOptions& o, SensorResult& res) {
    if (!FitAndJudge(train, binned, split, o.offset_terms, "error before",
                     res.holdout_before_offset, res.error_before, res))
        return false;
    const std::optional<model::Model>& sens = res.declared_sensitivity;
    const double inv_s = sens ? MeanInverseSensitivity(binned, *sens, split.held) : kNan;
    const std::optional<LsFit> after = FitAndJudge(train, binned, split, sel.terms, "error after",
                                                   res.holdout_after_offset, res.error_after, res);
    if (!after) return false;
    ExpectedAfter(*after, train.AllDesign(sel.terms)(split.held, Eigen::all), inv_s, &res);
    res.heldout_gain_v2 = res.heldout_slope = res.heldout_gain_z = kNan;
    if (sel.terms.size() == gate_base.size()) return true;
    const MatrixXd none(static_cast<Index>(binned.size()), 0);
    const VectorXd r_base = HeldResidual(binned, train, split, train.AllDesign(gate_base), none);
    const VectorXd r_sel = HeldResidual(binned, train, split, train.AllDesign(sel.terms), none);
    const Gain g = HeldOutGain(r_base, r_sel, split.held_block, train.hac_lag);
    res.heldout_gain_v2 = g.mean_v2;
    res.heldout_slope = g.slope;
    res.heldout_gain_z = g.z;
    // Beyond its noise (z) and never at the cost of the held-out drift.
    const bool drift_ok = !std::isfinite(res.error_before.drift_dph) ||
                          !std::isfinite(res.error_after.drift_dph) ||
                          res.error_after.drift_dph <= res.error_before.drift_dph;
    const bool gain = std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0;
    if (gain && !drift_ok)
        res.notes.push_back(
            "the chosen terms lowered the held-out RMS but raised the held-out "
            "drift (" +
            text::Sig(res.error_before.drift_dph, 3) + " -> " +
            text::Sig(res.error_after.drift_dph, 3) + " deg/h): not added");
    return gain && drift_ok;
}

// A time shape that predicts the warm-up's held-out blocks at least as well (rule kRejected: not
// attributed) or that the warm-up does not add to (kAmbiguous); what: the term and the rival's
// share of the blocks' squared residual; feature: the rival's generic feature (time channel).
void RivalVerdict(Decision rule, const std::string& what, const char* rival, const char* feature,
                  const LocalizedCheck& c, CandidateResult& r, SensorResult& res) {
    const std::string figures = " (" + what + " % of the squared residual, the warm-up " +
                                text::Sig(100.0 * c.drop, 3) + " %";
    const std::string sep = "to separate: " + SeparationFromTime("warmup", feature);
    if (rule == Decision::kRejected) {
        const std::string why =
            "warmup" + figures + "; " + rival + " predicts them at least as well; " + sep + ")";
        r.note = "not attributed: " + why + "; " + c.note;
        res.not_attributed.push_back(why);
    } else {
        const std::string why = "warmup vs " + std::string(feature) + " [time]" + figures +
                                "; the data do not tell one from the other): " + sep;
        r.decision = Decision::kAmbiguous;
        r.note = "ambiguous: " + why + "; " + c.note;
        res.ambiguities.push_back(why);
    }
}

// The warm-up's localized check (localized.hpp) on the chosen terms; the noise measured on their
// residual over all bins.
void WarmupStep(const BinnedRun& binned, const Context& train, const Candidate& warmup,
                const AnalysisOptions& o, Selection& sel, SensorResult& res) {
    if (warmup.effect.empty()) return;
    const Context all =
        MakeContext(binned, AllRows(binned.size()), train.t0, o, train.nuisance_all);
    const LsFit f = FitLs(all.Design(sel.terms), all.y, all.segment, 0);
    if (!f.ok) return;
    const Surrogates s = MakeSurrogates(binned, f.residuals, o);
    const LocalizedCheck c = CheckWarmup(binned, all, sel.terms, warmup, s, o);
    CandidateResult r{"warmup", c.term, Decision::kRejected, c.z2, kNan, 0, c.note, c.effect_rms_v};
    r.grid_edge = c.grid_edge;
    if (!c.tested) {
        r.decision = Decision::kNotTested;
        res.could_not_test.push_back("warmup: " + c.note);
    } else if (c.drift_rule && *c.drift_rule != Decision::kAdded) {
        const std::string what = c.term +
                                 " at the upper end of its grid; on its held-out blocks a linear "
                                 "drift in time removes " +
                                 text::Sig(100.0 * c.drift_drop, 3);
        RivalVerdict(*c.drift_rule, what, "the drift", "time since start", c, r, res);
    } else if (c.step_rule && *c.step_rule != Decision::kAdded) {
        const std::string what = c.term + "; on its held-out blocks a one-time step at " +
                                 text::Sig(c.step_s, 3) + " s from the start removes " +
                                 text::Sig(100.0 * c.step_drop, 3);
        RivalVerdict(*c.step_rule, what, "the step", "step", c, r, res);
    } else if (c.passes) {
        r.decision = Decision::kAdded;
        sel.terms.push_back(c.term);
        sel.added_effects.push_back("warmup");
        sel.x = train.Design(sel.terms);
    }
    res.candidates.push_back(r);
}

std::string UnitOf(const BinnedRun& binned, const AnalysisOptions& o, const std::string& effect) {
    for (const Candidate& c : OffsetCandidates(binned, o))
        if (c.effect == effect) return c.unit;
    return "";
}

// What became of the chosen terms: the warm-up stands on its localized check, the others on the
// held-out confirmation.
void Record(const BinnedRun& binned, const AnalysisOptions& o, bool confirmed, Selection& sel,
            SensorResult& res) {
    const size_t nd = o.offset_terms.size();
    std::vector<std::string> kept = o.offset_terms, kept_effects;
    for (size_t k = nd; k < sel.terms.size(); ++k) {
        const std::string& effect = sel.added_effects[k - nd];
        if (confirmed || effect == "warmup") {
            res.added.push_back({effect, sel.terms[k], UnitOf(binned, o, effect)});
            kept.push_back(sel.terms[k]);
            kept_effects.push_back(effect);
        } else {
            res.unconfirmed.push_back(effect);
        }
    }
    sel.terms = kept;
    sel.added_effects = kept_effects;
    for (CandidateResult& c : res.candidates)
        if (c.decision == Decision::kAdded && !confirmed && c.effect != "warmup") {
            c.decision = Decision::kRejected;
            c.note =
                "chosen on the training bins, not confirmed on the held-out bins "
                "(prediction slope " +
                text::Sig(res.heldout_slope, 3) + ", " + text::Sig(res.heldout_gain_z, 3) +
                " standard errors, need " + text::Sig(o.gate_min_z, 3) + "; squared error change " +
                text::Sig(-res.heldout_gain_v2, 3) + " V^2)";
        }
}

// The candidates not chosen, tested again with a warm-up the localized check added (and the terms
// already chosen) in the base model: chosen before it, a transient the model lacks inflates their
// noise and can mask one of them (a supply effect under a warm-up: rejected by the forward steps
// while the same regressor, as a generic feature, explained the held-out residual). On the
// training bins after the warm-up has decayed (3 tau): a transient confined to the first blocks is
// what blocked cross-validation cannot predict, and every candidate's CV gain would measure that
// instead of itself. Only adds: what the first choice added stays.
void ChooseAgainWithWarmup(const Context& train, const BinnedRun& binned, const AnalysisOptions& o,
                           Selection& sel, SensorResult& res) {
    const auto w = std::find(sel.added_effects.begin(), sel.added_effects.end(), "warmup");
    if (w == sel.added_effects.end()) return;
    const std::string warm_term =
        sel.terms[o.offset_terms.size() + static_cast<size_t>(w - sel.added_effects.begin())];
    std::vector<Index> after;
    const double tau_s = ParamOf(warm_term);
    for (Index row : train.rows)
        if (binned.bins()[static_cast<size_t>(row)].time_since_power_s > 3.0 * tau_s)
            after.push_back(row);
    if (static_cast<int>(after.size()) < 3 * o.cv_blocks + 10) return;
    std::vector<Candidate> pool;
    for (const Candidate& c : OffsetCandidates(binned, o))
        if (c.why_not.empty() && c.effect != "warmup" &&
            std::find(sel.added_effects.begin(), sel.added_effects.end(), c.effect) ==
                sel.added_effects.end())
            pool.push_back(c);
    if (pool.empty()) return;
    AnalysisOptions with = o;
    with.offset_terms = sel.terms;
    const Context train_with =
        MakeContext(binned, std::move(after), train.t0, with, train.nuisance_all);
    // The floor of the model with the warm-up fitted on every training bin: fitted on the bins
    // after it, the warm-up's coefficient says nothing of the first ones.
    Selection again =
        SelectOffsetTerms(train_with, std::move(pool), DeclaredFloor(train, binned, with), with);
    for (const CandidateResult& r : again.candidates)
        for (CandidateResult& c : res.candidates)
            if (c.effect == r.effect) {
                c = r;
                if (r.decision == Decision::kAdded)
                    c.note += std::string(c.note.empty() ? "" : "; ") + "chosen with " + warm_term +
                              " in the model, on the bins after 3 tau";
            }
    for (size_t k = sel.terms.size(); k < again.terms.size(); ++k)
        sel.terms.push_back(again.terms[k]);
    for (const std::string& e : again.added_effects) sel.added_effects.push_back(e);
    for (Selection::JointPair p : again.joint_pairs) {
        p.ambiguous_index += sel.ambiguous.size();
        sel.joint_pairs.push_back(p);
    }
    for (const std::string& a : again.ambiguous) sel.ambiguous.push_back(a);
    sel.x = train.Design(sel.terms);
}

// A generic shape (temp_knot) earns its place on the held-out bins by itself: the held-out gate
// (Confirm) judges the chosen terms together, and a knot chosen on the training bins beside a
// real effect rode along with it (the rig's held-out ramp runs: temp_rate + knot, cubic + knot,
// held-out error the same with the knot or without). Taken out unless the model with it predicts
// the held-out bins better than the model without it, beyond gate_min_z standard errors.
bool GenericShapeEarnsItsPlace(const Context& train, const BinnedRun& binned, const Split& split,
                               const AnalysisOptions& o, Selection& sel, SensorResult& res) {
    const size_t nd = o.offset_terms.size();
    for (size_t k = nd; k < sel.terms.size(); ++k) {
        if (sel.added_effects[k - nd] != "temp_knot") continue;
        std::vector<std::string> without = sel.terms;
        without.erase(without.begin() + static_cast<long>(k));
        const MatrixXd none(static_cast<Index>(binned.size()), 0);
        const VectorXd r_wo = HeldResidual(binned, train, split, train.AllDesign(without), none);
        const VectorXd r_w = HeldResidual(binned, train, split, train.AllDesign(sel.terms), none);
        if (r_wo.size() == 0 || r_w.size() != r_wo.size()) return false;
        const Gain g = HeldOutGain(r_wo, r_w, split.held_block, train.hac_lag);
        if (std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0) return false;
        const std::string why =
            "temp_knot (" + sel.terms[k] +
            " adds nothing on the held-out bins with the other terms in: " + text::Sig(g.z, 3) +
            " standard errors, need " + text::Sig(o.gate_min_z, 3) + ")";
        res.not_attributed.push_back(why);
        for (CandidateResult& c : res.candidates)
            if (c.effect == "temp_knot")
                c.decision = Decision::kRejected, c.note = "not attributed: " + why;
        sel.terms.erase(sel.terms.begin() + static_cast<long>(k));
        sel.added_effects.erase(sel.added_effects.begin() + static_cast<long>(k - nd));
        sel.x = train.Design(sel.terms);
        return true;
    }
    return false;
}

std::vector<std::string> GateBase(const AnalysisOptions& o, const Selection& sel) {
    std::vector<std::string> base = o.offset_terms;
    for (size_t k = o.offset_terms.size(); k < sel.terms.size(); ++k)
        if (sel.added_effects[k - o.offset_terms.size()] == "warmup") base.push_back(sel.terms[k]);
    return base;
}

}  // namespace

Selection OffsetStep(const BinnedRun& binned, const Split& split, double t0,
                     const AnalysisOptions& o, const MatrixXd& nuisance_all, SensorResult& res) {
    const Context train = MakeContext(binned, split.train, t0, o, nuisance_all);
    Candidate warmup;
    Selection sel = Choose(train, binned, o, res, warmup);
    WarmupStep(binned, train, warmup, o, sel, res);
    ChooseAgainWithWarmup(train, binned, o, sel, res);
    bool confirmed = Confirm(train, binned, split, sel, GateBase(o, sel), o, res);
    if (confirmed && GenericShapeEarnsItsPlace(train, binned, split, o, sel, res))
        confirmed = Confirm(train, binned, split, sel, GateBase(o, sel), o, res);
    if (confirmed) {
        const Context all = MakeContext(binned, AllRows(binned.size()), t0, o, nuisance_all);
        const LsFit f = FitLs(all.Design(sel.terms), all.y, all.segment, 0);
        const Surrogates s = MakeSurrogates(binned, f.ok ? f.residuals : VectorXd(), o);
        if (!Displace(train, binned, split, s, sel, o, res).empty())
            confirmed = Confirm(train, binned, split, sel, GateBase(o, sel), o, res);
    }
    Record(binned, o, confirmed, sel, res);
    JointPairFates(sel, confirmed, res);
    sel.x = train.Design(sel.terms);
    return sel;
}

namespace {

// The warm-up's time constant refined between its grid's neighbours (golden section on log tau,
// residual sum of squares on all bins with every other term in): the grid's spacing is coarser
// than the data resolve a strong transient.
std::string RefineWarmup(const Context& all, const std::vector<std::string>& terms, size_t k) {
    const double tau = ParamOf(terms[k]);
    auto rss = [&](double log_tau) {
        std::vector<std::string> t = terms;
        t[k] = model::WarmupTerm(std::exp(log_tau));
        const LsFit f = FitLs(all.Design(t), all.y, all.segment, 0);
        return f.ok ? f.rss : INFINITY;
    };
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = std::log(tau / 1.25), b = std::log(tau * 1.25);
    for (int it = 0; it < 14; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        if (rss(c) < rss(d))
            b = d;
        else
            a = c;
    }
    return model::WarmupTerm(std::exp(0.5 * (a + b)));
}

// The standard error of a searched term's parameter from the fit linearised in it: the column of
// d(term)/d(param) times its coefficient added to the model; its coefficient is the parameter's
// correction and its standard error the parameter's (the other coefficients free).
double ParamStderr(const Context& all, const std::vector<std::string>& terms, size_t k,
                   double coeff) {
    const double p = ParamOf(terms[k]);
    const std::string name = terms[k].substr(0, terms[k].find('('));
    auto term_at = [&](double v) { return model::ParamTerm(name, v); };
    // A knot is a position (any sign, 0.1 degC in its name): a step of kKnotStepC; the scale
    // parameters a relative step.
    const bool knot = name.rfind("knot_", 0) == 0;
    const double step = knot ? kKnotStepC : kParamStepRel * p;
    const VectorXd d = (all.binned->Column(term_at(p + step), all.t0)(all.rows) -
                        all.binned->Column(term_at(p - step), all.t0)(all.rows)) /
                       (2.0 * step) * coeff;
    const MatrixXd x0 = all.Design(terms);
    MatrixXd x(x0.rows(), x0.cols() + 1);
    x << x0, d;
    const LsFit f = FitLs(x, all.y, all.segment, all.hac_lag);
    return f.ok && d.allFinite() ? std::sqrt(f.covariance(x0.cols(), x0.cols())) : kNan;
}

}  // namespace

void FinalModels(const BinnedRun& binned, const std::vector<std::string>& terms_in, double t0,
                 const AnalysisOptions& o, const MatrixXd& nuisance_all, SensorResult& res) {
    const Context all = MakeContext(binned, AllRows(binned.size()), t0, o, nuisance_all);
    const LsFit fd = FitLs(all.Design(o.offset_terms), all.y, all.segment, all.hac_lag);
    if (fd.ok) {
        res.declared_offset = FitModel(o.offset_terms, t0, binned, all.rows, fd);
        res.residual_all_rms_v = std::sqrt(fd.rss / static_cast<double>(binned.size()));
    } else {
        res.could_not_test.push_back("declared offset model on all bins: " + fd.why);
    }
    std::vector<std::string> terms = terms_in;
    for (size_t k = o.offset_terms.size(); k < terms.size(); ++k)
        if (terms[k].rfind("warmup(", 0) == 0) {
            const std::string refined = RefineWarmup(all, terms, k);
            for (AddedEffect& a : res.added)
                if (a.term == terms[k]) a.term = refined;
            terms[k] = refined;
        }
    const LsFit fe = FitLs(all.Design(terms), all.y, all.segment, all.hac_lag);
    if (!fe.ok) {
        res.could_not_test.push_back("extended model: " + fe.why);
        return;
    }
    res.extended_offset = FitModel(terms, t0, binned, all.rows, fe);
    res.residual_all_extended_rms_v = std::sqrt(fe.rss / static_cast<double>(binned.size()));
    res.floor_offset_rms_v = NoiseFloor(binned.bins(), fe.residuals).offset_rms_v;
    for (size_t k = o.offset_terms.size(); k < terms.size(); ++k) {
        const auto i = static_cast<Index>(k);
        for (AddedEffect& a : res.added) {
            if (a.term != terms[k]) continue;
            a.coefficient = fe.coeffs[i];
            a.stderr_ = std::sqrt(fe.covariance(i, i));
            a.param = ParamOf(terms[k]);
            // thermometer_lag's time constant is temp_rate's (not searched): no stderr of its own.
            if (std::isfinite(a.param) && a.effect != "thermometer_lag")
                a.param_stderr = ParamStderr(all, terms, k, fe.coeffs[i]);
        }
    }
}

}  // namespace gyrocal::analysis::detail
