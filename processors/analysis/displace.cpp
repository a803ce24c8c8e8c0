// Step 8's guards (analyze.hpp, steps.hpp): a named term against the time-shaped generic features
// (drift, slow transient, step, periodic), the table-angle confound, the edge flags.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/null.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/residual.hpp"
#include "processors/analysis/steps.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

double ParamOf(const std::string& term) {
    const size_t open = term.find('(');
    if (open == std::string::npos) return kNan;
    char* end = nullptr;
    const double v = std::strtod(term.c_str() + open + 1, &end);
    return end && *end == ')' ? v : kNan;
}

// The measurement that tells a candidate from a time-shaped shape.
std::string SeparationFromTime(const std::string& effect, const std::string& feature) {
    if (effect == "warmup" && feature == "step")
        return "a second power cycle later in the run (a warm-up restarts with it, a one-time "
               "shift does not), or a longer dwell right after power-on";
    if (feature == "step")
        return "the same temperatures visited from both sides before and after the step's time "
               "(a one-time shift stays whatever the temperature does; " +
               effect +
               " follows the temperature's path), e.g. a setpoint approached from above before "
               "and after the event";
    if (feature == "periodic")
        return "a run with another schedule of ramps and dwells (a periodic disturbance keeps its "
               "period; " +
               effect + " follows the profile)";
    if (effect == "warmup")
        return "a second power cycle later in the run (a warm-up restarts with it, a slow drift "
               "does not)";
    return "the same setpoints visited again later in the run, or a second run (a drift in time "
           "grows between the visits; " +
           effect + " repeats)";
}

namespace {

// The static temperature shapes beyond a cubic: what temp_cubic is set against.
bool TemperatureShape(const Family& f) {
    return f.channel == "temperature" &&
           (f.name == "temperature^4" || f.name.rfind("spline knot", 0) == 0);
}

struct TermVsFeatures {
    NullVerdict with, without;  // each family with every term in, and without this one
};

bool Improves(const Gain& g, const AnalysisOptions& o) {
    return std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0;
}

bool Significant(const NullVerdict& v, size_t f) {
    return std::isfinite(v.z[f]) && v.z[f] > v.threshold &&
           v.fits[f].r1.squaredNorm() < v.fits[f].r0.squaredNorm();
}

// Takes term k out of the selection with its verdict.
void TakeOut(size_t k, Decision d, const std::string& why, Selection& sel, SensorResult& res) {
    const size_t nd = sel.terms.size() - sel.added_effects.size();
    const std::string effect = sel.added_effects[k - nd];
    sel.terms.erase(sel.terms.begin() + static_cast<long>(k));
    sel.added_effects.erase(sel.added_effects.begin() + static_cast<long>(k - nd));
    for (CandidateResult& c : res.candidates)
        if (c.effect == effect)
            c.decision = d,
            c.note = (d == Decision::kAmbiguous ? "ambiguous: " : "not attributed: ") + why;
}

// One added term against every time-shaped family (and temp_cubic also against the temperature
// shapes beyond it: (T - T0)^4 and one spline knot above or below), on the held-out bins, every
// model fitted on the training bins:
// - kept when the term lowers the held-out error with the feature in (HeldOutGain, gate_min_z);
// - a mimic (not attributed) when it does not and the feature still explains held-out data with
//   the term in (the features' null);
// - when the feature explains held-out data alone but not with the term in, the two are told
//   apart by two statistical tests at the held-out gate's level gate_min_z (one standard for every
//   held-out comparison, not a constant of this rule):
//   (1) forecast encompassing: the term's held-out prediction with the feature in is regressed on
//       what the feature leaves (HeldOutGain's slope); a slope beyond gate_min_z standard errors
//       means the term carries held-out information the feature lacks (its size, fitted on the
//       training bins, may still overshoot): not the same explanation, the term is kept;
//   (2) equal predictive accuracy (Diebold-Mariano, LossDifferenceZ): the held-out squared errors
//       of the model with the term and of the model with the feature instead. Within gate_min_z
//       standard errors of each other: the data cannot tell them apart, a twin (ambiguous); the
//       feature significantly better: it encompasses the term (not attributed); the term
//       significantly better: kept.
// Returns the verdict text, empty when kept.
std::string Judge(const std::vector<Family>& fams, const TermVsFeatures& t,
                  const std::string& effect, const Split& split, int hac_lag,
                  const AnalysisOptions& o, Decision& d) {
    for (size_t f = 0; f < fams.size(); ++f) {
        const FamilyFit &w = t.with.fits[f], &wo = t.without.fits[f];
        if (w.r1.size() == 0 || wo.r1.size() != w.r1.size()) continue;
        const std::string what = fams[f].name + " [" + fams[f].channel + "]";
        // A feature without a time shape competes only with the candidate of its own kind: a
        // temperature shape beyond the cubic with temp_cubic.
        if (!fams[f].competes && effect != "temp_cubic") continue;
        // A static temperature shape that still explains held-out data with the cubic in: the
        // offset's dependence on temperature goes beyond a cubic, and the cubic is but its
        // projection on dT^3 (it lowers the error without being the effect). The shape is not a
        // candidate: reported as what is left, the cubic not attributed.
        if (!fams[f].competes && Significant(t.with, f)) {
            d = Decision::kRejected;
            return effect + " (the offset's temperature shape goes beyond a cubic: " + what +
                   " explains the held-out residual with the cubic in, standardised " +
                   text::Sig(t.with.z[f], 3) + " above " + text::Sig(t.with.threshold, 3) +
                   "; the cubic is part of a shape the candidates do not have)";
        }
        // Alone, a spline's knot is the cubic's near twin over most of the range: it can only
        // show what is beyond the cubic (above), never stand in for it.
        if (fams[f].name.rfind("spline knot", 0) == 0) continue;
        const Gain term_given_feature = HeldOutGain(wo.r1, w.r1, split.held_block, hac_lag);
        if (Improves(term_given_feature, o)) continue;
        if (Significant(t.with, f)) {
            d = Decision::kRejected;
            return effect + " (" + what +
                   " explains its held-out residual with the term in the "
                   "model, standardised " +
                   text::Sig(t.with.z[f], 3) + " above " + text::Sig(t.with.threshold, 3) +
                   "; the term nothing with it in)";
        }
        if (!Significant(t.without, f) || term_given_feature.z > o.gate_min_z) continue;
        // > 0: the feature alone predicts the held-out bins better than the term alone.
        const double loss_z = LossDifferenceZ(w.r0, wo.r1, split.held_block, hac_lag);
        if (loss_z > o.gate_min_z) {
            d = Decision::kRejected;
            return effect + " (" + what +
                   " alone predicts its held-out data better than the term alone, by " +
                   text::Sig(loss_z, 3) + " standard errors of the squared-error difference; the " +
                   "term adds nothing with it in)";
        }
        if (std::fabs(loss_z) <= o.gate_min_z) {
            d = Decision::kAmbiguous;
            return effect + " vs " + what +
                   ": either explains the held-out data as well as the other (squared errors " +
                   "within " + text::Sig(std::fabs(loss_z), 2) + " standard errors), neither " +
                   "adds to the other; to separate: " + SeparationFromTime(effect, fams[f].name);
        }
    }
    return "";
}

}  // namespace

std::vector<std::string> Displace(const Context& train, const BinnedRun& binned, const Split& split,
                                  const Surrogates& s, Selection& sel, const AnalysisOptions& o,
                                  SensorResult& res) {
    std::vector<std::string> out;
    const size_t nd = o.offset_terms.size();
    if (sel.terms.size() == nd || s.noise.empty()) return out;
    std::vector<Family> fams;
    for (Family& f : FeatureFamilies(binned, train, train.AllDesign(o.offset_terms), o))
        if (f.competes || TemperatureShape(f)) fams.push_back(std::move(f));
    const VectorXd y = BinValues(binned);
    const HeldOutSearch with(train.AllDesign(sel.terms), train.rows, split.held, fams);
    if (!with.ok()) return out;
    TermVsFeatures t;
    t.with = JudgeOnNull(with, y, s.noise, o.feature_fpr);
    for (size_t k = sel.terms.size(); k-- > nd;) {
        std::vector<std::string> without = sel.terms;
        without.erase(without.begin() + static_cast<long>(k));
        const HeldOutSearch wo(train.AllDesign(without), train.rows, split.held, fams);
        if (!wo.ok()) continue;
        t.without = JudgeOnNull(wo, y, s.noise, o.feature_fpr);
        const std::string effect = sel.added_effects[k - nd];
        // The warm-up is checked on its own support (localized.hpp), where the held-out blocks
        // of this comparison hold little of it; the joint search (analyze.cpp) weighs it against
        // the time shapes instead.
        if (effect == "warmup") continue;
        Decision d = Decision::kRejected;
        const std::string why = Judge(fams, t, effect, split, train.hac_lag, o, d);
        if (why.empty()) continue;
        (d == Decision::kAmbiguous ? res.ambiguities : res.not_attributed).push_back(why);
        TakeOut(k, d, why, sel, res);
        out.push_back(effect);
    }
    if (!out.empty()) sel.x = train.Design(sel.terms);
    return out;
}

void JointPairFates(Selection& sel, bool confirmed, SensorResult& res) {
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
    for (const std::string& a : sel.ambiguous) {
        const size_t vs = a.find(" vs ");
        const size_t end = a.find(" (", vs);
        const std::string first = a.substr(0, vs);
        const std::string second = a.substr(vs + 4, end == std::string::npos ? end : end - vs - 4);
        res.ambiguities.push_back(a + ": to separate: " + Separation(first, second));
    }
}

// Shape parameters at an end of their searched range (item 2 of step 4's search; the generic
// features' own in residual.cpp): on every candidate, and listed in `edges` for those chosen on
// the training bins and the features that explain held-out data.
void Edges(const BinnedRun& binned, const AnalysisOptions& o, SensorResult& res) {
    const std::vector<Candidate> cands = OffsetCandidates(binned, o);
    for (CandidateResult& c : res.candidates) {
        if (!c.grid_edge || c.term.empty()) continue;
        if (c.effect == "temp_knot") {
            c.edge =
                "the knot at an end of its searched range (20 % of the range in from an end of "
                "the still data): the shape may bend closer to that end";
            continue;
        }
        for (const Candidate& k : cands) {
            if (k.effect != c.effect || k.grid.size() < 2) continue;
            const bool upper = c.term == k.grid.back();
            const double lo = ParamOf(k.grid.front()), hi = ParamOf(k.grid.back());
            const char* param = c.effect == "temp_rate" || c.effect == "thermometer_lag"
                                    ? "dT/dt time constant"
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
        if (c.effect == "sf_asymmetry")
            c.decision = Decision::kRejected, c.note = "not attributed: " + why;
}

}  // namespace gyrocal::analysis::detail
