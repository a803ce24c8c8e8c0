#include "processors/analysis/outcome.hpp"

#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/candidates.hpp"

namespace gyrocal::analysis::detail {

std::string MeasurementToTest(const std::string& effect) {
    if (effect == "temp_rate")
        return "temperature ramps (at least a few degC/min) recorded at rest";
    if (effect == "thermometer_lag")
        return "temperature ramps recorded at rest, with temp_rate testable";
    if (effect == "hysteresis")
        return "ramps up and down through the same temperatures, with dwells between them";
    if (effect == "temp_cubic") return "dwells at 5 or more temperatures spread over the range";
    if (effect == "temp_knot")
        return "dwells or ramps over 8 or more 2-degC temperature bands, with temp_cubic testable";
    if (effect == "supply") return "the supply voltage recorded with every sample";
    if (effect == "warmup")
        return "recording from power-on (a power record) with a dwell right after it";
    if (effect == "sf_asymmetry") return "turns in both directions at 3 or more temperatures";
    return "more data in which it varies";
}

double FloorBound(double floor_v, double prediction_v, double k) {
    if (!std::isfinite(floor_v)) return kNan;
    const double p = std::isfinite(prediction_v) ? prediction_v : 0.0;
    return std::sqrt(floor_v * floor_v * (1.0 + 9.0 * k * k) + 9.0 * p * p);
}

namespace {

std::string List(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& e : v) s += (s.empty() ? "" : ", ") + e;
    return s;
}

std::string Mv(double v) { return text::Sig(v * 1e3, 3) + " mV"; }

// "correlates with ..." : the generic features that explain held-out data, strongest first.
std::string Correlates(const SensorResult& r) {
    std::vector<std::string> c;
    for (const FeatureResult& f : r.features) {
        if (!f.explains_heldout || c.size() >= 2) continue;
        c.push_back(f.feature + " [" + f.channel + "; " + f.detail +
                    (f.edge.empty() ? std::string() : " (" + f.edge + ")") + "; removes " +
                    text::Sig(100.0 * f.heldout_drop, 2) +
                    " % of the held-out squared residual, z " + text::Sig(f.heldout_z, 3) + "]");
    }
    if (c.empty()) return "correlates with none of the generic features on held-out data";
    return "correlates with " + List(c);
}

std::string Where(const SensorResult& r) {
    std::string s;
    if (!r.windows_above.empty()) {
        // The windows above what the run's noise leaves in a window of their size, worst first.
        for (size_t k = 0; k < r.windows_above.size() && k < 2; ++k) {
            const WindowExcess& w = r.windows_above[k];
            s += std::string(k ? ", " : "far from the floor at ") + w.where + " (" + Mv(w.rms_v) +
                 " RMS where the noise leaves " + Mv(w.expected_rms_v) + ")";
        }
        return s;
    }
    const ResidualDiagnostics& d = r.residual;
    if (std::isfinite(d.worst_time.rms_v))
        s += "largest at " + text::Sig(d.worst_time.lo, 4) + "-" + text::Sig(d.worst_time.hi, 4) +
             " s from the start (" + Mv(d.worst_time.rms_v) + " RMS)";
    if (std::isfinite(d.worst_temp.rms_v))
        s += std::string(s.empty() ? "" : ", ") + "at " + text::Sig(d.worst_temp.lo, 3) + ".." +
             text::Sig(d.worst_temp.hi, 3) + " degC (" + Mv(d.worst_temp.rms_v) + " RMS)";
    return s;
}

// What would pin the coefficients of an effect (or the declared terms) better than this run did.
std::string ToPin(const std::string& effect) {
    if (effect == "supply") return "a run with more supply variation";
    if (effect == "temp_rate") return "a run with more or faster temperature ramps";
    if (effect == "hysteresis") return "a run with more temperature reversals";
    if (effect == "warmup") return "a dwell right after power-on, or another power cycle";
    if (effect == "temp_cubic" || effect == "temp_knot")
        return "dwells spread over a wider temperature range";
    return "a longer run (the run's slow noise sets the offset's level)";
}

// "the extended model, if right, is expected to miss another run by 1.25x the true model's
// error (...)": the transfer check's figures (SensorResult::transfer_*).
std::string TransferText(const SensorResult& r) {
    const bool declared = r.transfer_term == "declared" || r.transfer_term.empty();
    return "its coefficients are not pinned well enough to predict another run: expected " +
           text::Sig(r.transfer_ratio, 3) + "x the true model's error there (the coefficients' " +
           "uncertainty under the run's own noise leaves " + Mv(r.transfer_model_rms_v) +
           " where the truth's error is " + Mv(r.transfer_truth_rms_v) + ", " +
           (declared ? std::string("most of it the declared terms'")
                     : "the " + r.transfer_term + " term adding " + Mv(r.transfer_term_rms_v)) +
           "; " + text::Sig(100.0 * r.transfer_miss_fraction, 2) + " % of such runs beyond " +
           "the criterion; " + ToPin(declared ? "" : r.transfer_term) + " would pin it)";
}

std::string Residual(const SensorResult& r) {
    return "held-out residual " + Mv(r.heldout_residual_rms_v) + " = " +
           text::Sig(r.excess_ratio, 2) + "x the floor bound " + Mv(r.floor_bound_rms_v);
}

}  // namespace

void Conclude(bool analysed, const AnalysisOptions& o, SensorResult& res) {
    int candidates = 0;
    for (const CandidateResult& c : res.candidates) {
        ++candidates;
        if (c.decision != Decision::kNotTested) continue;
        res.untested.push_back(c.effect);
        res.to_test.push_back(c.effect + ": " + MeasurementToTest(c.effect));
    }
    res.heldout_residual_rms_v =
        res.added.empty() ? res.error_before.offset_rms_v : res.error_after.offset_rms_v;
    const double k = std::isfinite(res.slow_noise_k) ? res.slow_noise_k
                     : o.slow_noise_floor_ratio >= 0 ? o.slow_noise_floor_ratio
                                                     : 1.0;
    res.floor_bound_rms_v = FloorBound(res.floor_offset_rms_v, res.floor_prediction_rms_v, k);
    res.excess_ratio = res.heldout_residual_rms_v / res.floor_bound_rms_v;
    bool traced = false;
    for (const FeatureResult& f : res.features) traced = traced || f.explains_heldout;
    // A candidate chosen on the training bins (z^2, blocked CV, size) that the held-out gate
    // refused: the run's two tests disagree, so it cannot say that nothing is missing
    // (processors/analysis/README.md#misses-of-the-12x-criterion: "adequate" with an unconfirmed
    // supply was 1.5-1.7x the truth's error on another run).
    const bool above = (std::isfinite(res.excess_ratio) && res.excess_ratio > 1.0) || traced ||
                       !res.windows_above.empty() || !res.unconfirmed.empty();
    const bool known = std::isfinite(res.excess_ratio);
    std::vector<std::string> added;
    for (const AddedEffect& a : res.added) added.push_back(a.effect);
    const std::string tail = above ? "; " + Where(res) + "; " + Correlates(res) : "";
    const std::string of =
        std::to_string(res.untested.size()) + " of " + std::to_string(candidates);
    const bool untestable = static_cast<double>(res.untested.size()) >
                            o.max_untested_fraction * static_cast<double>(candidates);
    std::string h;
    if (!analysed || !known || untestable) {
        res.outcome = Outcome::kNotTestable;
        h = (analysed ? "not testable: " : "not analysed: not testable: ") + of +
            " candidates could not be tested (" + List(res.untested) +
            "); to test them: " + List(res.to_test);
        if (!analysed) h += "; too few still bins (" + std::to_string(res.n_bins) + ")";
        if (known) h += "; " + Residual(res) + tail;
    } else if (!res.ambiguities.empty()) {
        res.outcome = Outcome::kAmbiguous;
        h = "ambiguous: " + List(res.ambiguities) +
            (added.empty() ? "" : "; added: " + List(added)) + "; " + Residual(res) + tail;
    } else if (added.empty()) {
        res.outcome = above ? Outcome::kUnexplained : Outcome::kAdequate;
        h = above ? "missing effect (unexplained residual): " + Residual(res) + tail
                  : "no missing effect: adequate, " + Residual(res);
    } else {
        // Explained, but not pinned: the extended model, taken as right, is expected to miss
        // another run by more than the transfer criterion (max_transfer_ratio).
        res.transfer_flagged = !above && o.max_transfer_ratio > 0 &&
                               std::isfinite(res.transfer_ratio) &&
                               res.transfer_ratio > o.max_transfer_ratio;
        const bool partly = above || res.transfer_flagged;
        res.outcome = partly ? Outcome::kPartlyExplained : Outcome::kExplained;
        h = std::string(added.size() > 1 ? "missing effects: " : "missing effect: ") + List(added) +
            (partly ? ", partly explained: " : ", explained: ") + Residual(res) + tail +
            (res.transfer_flagged ? "; " + TransferText(res) : "");
    }
    if (res.outcome != Outcome::kNotTestable && !res.untested.empty())
        h += "; not tested: " + List(res.untested);
    if (!res.not_attributed.empty()) h += "; not attributed: " + List(res.not_attributed);
    if (!res.unconfirmed.empty())
        h += "; not confirmed on the held-out data: " + List(res.unconfirmed) +
             " (chosen on the training bins; the run cannot tell whether it is missing)";
    res.headline = h;
    res.verdict = h;
}

}  // namespace gyrocal::analysis::detail
