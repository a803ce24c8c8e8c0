#include "processors/acceptance/evaluate.hpp"

#include <algorithm>
#include <cstdio>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"
#include "processors/model/inputs.hpp"

namespace gyrocal::acceptance {

namespace {

constexpr int kGridPoints = 201;

// A unit at rest at temp_c, warmed up, at nominal supply, on neither branch: what "the model at T"
// means for a set whose terms also read dT/dt, the branch, the supply or the warm-up (a final set
// fitted on every still sample); a polynomial reads temp_c alone.
model::ModelInputs At(const model::Model& m, double temp_c) {
    return model::SteadyStateInputs(m, temp_c);
}

// The temperatures of the grid over a model's valid range; empty when the range is not finite.
std::vector<double> Grid(const model::Model& m) {
    if (!std::isfinite(m.temp_min_c) || !std::isfinite(m.temp_max_c) || m.temp_max_c < m.temp_min_c)
        return {};
    std::vector<double> t;
    for (int i = 0; i < kGridPoints; ++i)
        t.push_back(m.temp_min_c + (m.temp_max_c - m.temp_min_c) * i / (kGridPoints - 1));
    return t;
}

Check Start(const std::string& key, double limit) {
    Check c;
    for (const LimitDef& d : LimitDefs())
        if (d.key == key) {
            c.key = key;
            c.unit = d.unit;
            c.kind = d.kind;
        }
    c.limit = limit;
    return c;
}

void Compare(Check& c, const Measure& m, Outcome when_unmeasured) {
    c.measured = m.value;
    c.measured_text = std::isnan(m.value) ? "-" : text::Sig(m.value, 3);  // inf stays "inf"
    c.note = m.note;
    if (std::isnan(m.value)) {
        c.outcome = when_unmeasured;
        return;
    }
    const bool ok = c.kind == "min" ? m.value >= c.limit : m.value <= c.limit;
    c.outcome = ok ? Outcome::kPass : Outcome::kFail;
}

std::string Joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& e : v) s += (s.empty() ? "" : "; ") + e;
    return s;
}

// The analysis' outcome (analyze.hpp, step 9) decides; its headline only explains.
Check Verdict(const UnitEvidence& u) {
    Check c = Start("no_unexplained_residual", 1);
    if (!u.analysis_verdict) {
        c.measured_text = "no analysis";
        c.note = "the run has no analysis of this unit (gyrocal analyze RUN)";
        return c;
    }
    const std::string& headline = *u.analysis_verdict;
    if (!u.analysis_outcome) {
        c.measured_text = "no outcome stored";
        c.note =
            "the newest analysis was stored without an outcome (by a gyrocal older than "
            "outcomes): run gyrocal analyze RUN again";
        return c;
    }
    const std::string& o = *u.analysis_outcome;
    c.measured_text = o + ": " + headline;
    if (o == "adequate") {
        c.outcome = Outcome::kPass;
    } else if (o == "explained") {
        // Explained by added terms: the unit is served only if a set carrying them was stored
        // (the fitter's set, judged above, lacks them by construction).
        c.outcome = u.analysis_stored_set ? Outcome::kPass : Outcome::kFail;
        if (!u.analysis_stored_set)
            c.note =
                "the analysis explains the residual with terms no stored set carries: run "
                "gyrocal analyze RUN again to store the extended set";
    } else if (o == "partly explained" || o == "unexplained residual") {
        c.outcome = Outcome::kFail;
        c.note = "the analysis leaves a residual above the floor: " + headline;
    } else if (o == "ambiguous") {
        // The data cannot say which of two shapes carries the effect: a compensation that carries
        // the wrong one fails wherever the two differ, so the unit is not served until the
        // measurement the headline names separates them.
        c.outcome = Outcome::kFail;
        c.note = "the analysis cannot tell two shapes apart: " + headline;
    } else if (o == "not testable") {
        c.note = "the analysis could not test this unit" +
                 (u.analysis_to_test.empty() ? std::string()
                                             : "; to test it: " + Joined(u.analysis_to_test));
    } else {
        c.measured_text = "outcome '" + o + "'";
        c.note = "the stored analysis outcome '" + o +
                 "' is not one this version reads (adequate, explained, partly explained, "
                 "unexplained residual, ambiguous, not testable)";
    }
    return c;
}

constexpr text::NameTable<Outcome, 3> kOutcomeNames{{{Outcome::kPass, "pass"},
                                                     {Outcome::kFail, "FAIL"},
                                                     {Outcome::kNotEvaluated, "not evaluated"}}};

}  // namespace

const char* ToString(Outcome o) { return text::NameOf(kOutcomeNames, o); }

Measure ResidualOverFloor(const UnitEvidence& u) {
    if (!u.has_calibration) return {NAN, "no coefficient set for this unit"};
    // The plateau set, when the final set is not it.
    const model::Model& offset = u.plateau_offset.term_names.empty() ? u.offset : u.plateau_offset;
    const model::Model& sensitivity =
        u.plateau_sensitivity.term_names.empty() ? u.sensitivity : u.plateau_sensitivity;
    const int dof =
        static_cast<int>(u.plateaus.size()) - static_cast<int>(offset.term_names.size());
    if (dof < 1)
        return {
            NAN,
            std::to_string(u.plateaus.size()) + " plateaus for " +
                std::to_string(offset.term_names.size()) +
                " offset terms leave no degree of freedom: the residual cannot show a wrong model"};
    try {
        const model::Evaluator off(offset), sens(sensitivity);
        double chi2 = 0;
        for (const PlateauPoint& p : u.plateaus) {
            const double slow_v =
                u.plateau_slow_noise_dps *
                std::abs(sens.Value(At(sensitivity, p.temp_c), model::RangePolicy::kClip));
            const double sigma = std::hypot(p.gyro_sem_v, slow_v);
            const double r =
                p.gyro_mean_v - off.Value(At(offset, p.temp_c), model::RangePolicy::kExtrapolate);
            if (!(sigma > 0) || !std::isfinite(r))
                return {NAN, "a plateau without a usable value or standard error"};
            chi2 += (r / sigma) * (r / sigma);
        }
        return {std::sqrt(chi2 / dof), ""};
    } catch (const model::ModelError& e) {
        return {NAN, std::string("the coefficient set is not usable: ") + e.what()};
    }
}

Measure OffsetChangeDps(const model::Model& offset, const model::Model& sensitivity) {
    const std::vector<double> grid = Grid(offset);
    if (grid.empty()) return {NAN, "the offset model has no valid temperature range"};
    try {
        const model::Evaluator off(offset), sens(sensitivity);
        double lo = INFINITY, hi = -INFINITY;
        for (double t : grid) {
            const double v = off.Value(At(offset, t), model::RangePolicy::kClip);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        const double s_mid = std::abs(sens.Value(
            At(sensitivity, 0.5 * (grid.front() + grid.back())), model::RangePolicy::kClip));
        if (!(s_mid > 0) || !std::isfinite(hi - lo))
            return {NAN, "offset or sensitivity not finite over the range"};
        return {(hi - lo) / s_mid, ""};
    } catch (const model::ModelError& e) {
        return {NAN, std::string("the coefficient set is not usable: ") + e.what()};
    }
}

Measure MaxSensitivityRelUncertaintyPct(const model::Model& sensitivity) {
    std::vector<double> grid = Grid(sensitivity);
    if (grid.empty()) grid = {sensitivity.t0_c};  // a mean or nominal value: one temperature
    try {
        const model::Evaluator sens(sensitivity);
        double worst = 0;
        for (double t : grid) {
            const model::Evaluation e =
                sens.Evaluate(At(sensitivity, t), model::RangePolicy::kClip);
            const double rel = 100.0 * std::sqrt(e.variance) / std::abs(e.value);
            if (!std::isfinite(rel))
                return {NAN, "sensitivity uncertainty unknown (method " + sensitivity.method +
                                 (sensitivity.method == "nominal" ? ": no turn was fitted)" : ")")};
            worst = std::max(worst, rel);
        }
        return {worst, ""};
    } catch (const model::ModelError& e) {
        return {NAN, std::string("the coefficient set is not usable: ") + e.what()};
    }
}

UnitVerdict Evaluate(const Limits& l, const UnitEvidence& u) {
    UnitVerdict v;
    v.sensor_id = u.sensor_id;
    const Measure none{NAN, "no coefficient set for this unit"};
    if (l.max_residual_rms_over_floor) {
        Check c = Start("max_residual_rms_over_floor", *l.max_residual_rms_over_floor);
        // Without a calibration the unit fails; without a degree of freedom it cannot be judged.
        Compare(c, ResidualOverFloor(u),
                u.has_calibration ? Outcome::kNotEvaluated : Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.max_offset_change_dps) {
        Check c = Start("max_offset_change_dps", *l.max_offset_change_dps);
        Compare(c, u.has_calibration ? OffsetChangeDps(u.offset, u.sensitivity) : none,
                Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.max_sensitivity_rel_uncertainty_pct) {
        Check c =
            Start("max_sensitivity_rel_uncertainty_pct", *l.max_sensitivity_rel_uncertainty_pct);
        Compare(c, u.has_calibration ? MaxSensitivityRelUncertaintyPct(u.sensitivity) : none,
                Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.min_plateaus) {
        Check c = Start("min_plateaus", *l.min_plateaus);
        Compare(c, {static_cast<double>(u.has_calibration ? u.n_plateaus : 0), ""}, Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.min_turns) {
        Check c = Start("min_turns", *l.min_turns);
        Compare(c, {static_cast<double>(u.has_calibration ? u.n_turns : 0), ""}, Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.no_unexplained_residual) v.checks.push_back(Verdict(u));
    const std::string why = u.has_calibration ? u.final_heldout_note : none.note;
    if (l.max_heldout_rate_rms_dps) {
        Check c = Start("max_heldout_rate_rms_dps", *l.max_heldout_rate_rms_dps);
        Compare(c, {u.final_heldout_rate_rms_dps, why},
                u.has_calibration ? Outcome::kNotEvaluated : Outcome::kFail);
        v.checks.push_back(c);
    }
    if (l.max_heldout_drift_dph) {
        Check c = Start("max_heldout_drift_dph", *l.max_heldout_drift_dph);
        Compare(c, {u.final_heldout_drift_dph, why},
                u.has_calibration ? Outcome::kNotEvaluated : Outcome::kFail);
        v.checks.push_back(c);
    }
    const auto any = [&](Outcome o) {
        return std::any_of(v.checks.begin(), v.checks.end(),
                           [o](const Check& c) { return c.outcome == o; });
    };
    v.outcome = any(Outcome::kFail)           ? Outcome::kFail
                : any(Outcome::kNotEvaluated) ? Outcome::kNotEvaluated
                                              : Outcome::kPass;
    return v;
}

std::string Summary(const UnitVerdict& v) {
    std::string out;
    for (const Check& c : v.checks) {
        if (c.outcome == Outcome::kPass) continue;
        std::string item = c.key + " ";
        if (c.kind == "require")
            item += c.outcome == Outcome::kFail ? "failed (" + c.measured_text + ")"
                                                : "not evaluated (" + c.note + ")";
        else if (c.outcome == Outcome::kFail && !std::isnan(c.measured))
            item += c.measured_text + (c.kind == "min" ? " < " : " > ") + text::Sig(c.limit, 3) +
                    " " + c.unit;
        else
            item += (c.outcome == Outcome::kFail ? "failed (" : "not evaluated (") + c.note + ")";
        out += (out.empty() ? "" : "; ") + item;
    }
    return v.sensor_id + ": " +
           (out.empty() ? std::string("pass") : std::string(ToString(v.outcome)) + ": " + out);
}

}  // namespace gyrocal::acceptance
