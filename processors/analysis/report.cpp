#include "processors/analysis/report.hpp"

#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"
#include "processors/model/json.hpp"

namespace gyrocal::analysis {

namespace {

using model::JsonNumber;

nlohmann::json Errors(const ErrorFigures& e) {
    return {{"offset_rms_v", JsonNumber(e.offset_rms_v)},
            {"rate_rms_dps", JsonNumber(e.rate_rms_dps)},
            {"drift_dph", JsonNumber(e.drift_dph)}};
}

nlohmann::json Windows(const std::vector<WindowRms>& w) {
    nlohmann::json a = nlohmann::json::array();
    for (const WindowRms& x : w)
        a.push_back({{"lo", JsonNumber(x.lo)},
                     {"hi", JsonNumber(x.hi)},
                     {"rms_v", JsonNumber(x.rms_v)},
                     {"bins", x.n}});
    return a;
}

nlohmann::json Beyond(const SensorResult& r) {
    using nlohmann::json;
    json f = json::array();
    for (const FeatureResult& x : r.features)
        f.push_back({{"feature", x.feature},
                     {"channel", x.channel},
                     {"detail", x.detail},
                     {"corr", JsonNumber(x.corr)},
                     {"heldout_z", JsonNumber(x.heldout_z)},
                     {"heldout_gain_v2", JsonNumber(x.heldout_gain_v2)},
                     {"heldout_after_rms_v", JsonNumber(x.heldout_after_rms_v)},
                     {"effect_rms_v", JsonNumber(x.effect_rms_v)},
                     {"heldout_drop", JsonNumber(x.heldout_drop)},
                     {"null_z", JsonNumber(x.null_z)},
                     {"null_threshold", JsonNumber(x.null_threshold)},
                     {"explains_heldout", x.explains_heldout},
                     {"at_edge_of_search", !x.edge.empty()},
                     {"edge", x.edge}});
    const ResidualDiagnostics& d = r.residual;
    return {{"features", f},
            {"residual",
             {{"rms_v", JsonNumber(d.rms_v)},
              {"lag1_autocorr", JsonNumber(d.lag1_autocorr)},
              {"trend_v_per_h", JsonNumber(d.trend_v_per_h)},
              {"trend_z", JsonNumber(d.trend_z)},
              {"period_s", JsonNumber(d.period_s)},
              {"period_amplitude_v", JsonNumber(d.period_amplitude_v)},
              {"period_power_ratio", JsonNumber(d.period_power_ratio)},
              {"by_time_s", Windows(d.by_time)},
              {"by_temp_c", Windows(d.by_temp)}}}};
}

// What the run itself gave: the windows far from the floor and the thresholds (analyze.hpp).
void FromRun(const SensorResult& r, nlohmann::json& j) {
    using nlohmann::json;
    json windows = json::array();
    for (const WindowExcess& w : r.windows_above)
        windows.push_back({{"where", w.where},
                           {"rms_v", JsonNumber(w.rms_v)},
                           {"expected_rms_v", JsonNumber(w.expected_rms_v)},
                           {"z", JsonNumber(w.z)},
                           {"bins", w.n}});
    j["windows_above"] = windows;
    j["thresholds_from_run"] = {
        {"slow_noise_k", JsonNumber(r.slow_noise_k)},
        {"slow_noise_measured", r.slow_noise_measured},
        {"noise", r.noise_note},
        {"surrogates", r.n_surrogates},
        {"feature_null_threshold", JsonNumber(r.feature_null_threshold)},
        {"window_null_threshold", JsonNumber(r.window_null_threshold)},
        {"claimed_false_positive_rate", JsonNumber(r.claimed_false_positive_rate)}};
}

}  // namespace

nlohmann::json ToJson(const SensorResult& r) {
    using nlohmann::json;
    json j;
    j["sensor_id"] = r.sensor_id;
    j["verdict"] = r.verdict;
    j["outcome"] = ToString(r.outcome);
    j["headline"] = r.headline;
    j["heldout_residual_rms_v"] = JsonNumber(r.heldout_residual_rms_v);
    j["floor_bound_rms_v"] = JsonNumber(r.floor_bound_rms_v);
    j["excess_ratio"] = JsonNumber(r.excess_ratio);
    j["untested"] = r.untested;
    j["to_test"] = r.to_test;
    j["not_attributed"] = r.not_attributed;
    j["absent_channels"] = r.absent_channels;
    j["edges"] = r.edges;
    j["ambiguities"] = r.ambiguities;
    FromRun(r, j);
    const nlohmann::json b = Beyond(r);
    j["features"] = b["features"];
    j["residual"] = b["residual"];
    json cands = json::array();
    for (const CandidateResult& c : r.candidates)
        cands.push_back({{"effect", c.effect},
                         {"term", c.term},
                         {"statistic", JsonNumber(c.z2)},
                         {"statistic_name", "z2 (coefficient^2 / robust variance)"},
                         {"cv_gain", JsonNumber(c.cv_gain)},
                         {"effect_rms_v", JsonNumber(c.effect_rms_v)},
                         {"decision", ToString(c.decision)},
                         {"step", c.step},
                         {"at_edge_of_search", c.grid_edge},
                         {"edge", c.edge},
                         {"note", c.note}});
    j["candidates"] = cands;
    json added = json::array();
    for (const AddedEffect& a : r.added)
        added.push_back({{"effect", a.effect},
                         {"term", a.term},
                         {"coefficient", JsonNumber(a.coefficient)},
                         {"stderr", JsonNumber(a.stderr_)},
                         {"unit", a.unit},
                         {"param", JsonNumber(a.param)},
                         {"param_stderr", JsonNumber(a.param_stderr)}});
    j["added"] = added;
    j["error_before"] = Errors(r.error_before);
    j["error_after"] = Errors(r.error_after);
    j["floor_rate_rms_dps"] = JsonNumber(r.floor_rate_rms_dps);
    j["floor_offset_rms_v"] = JsonNumber(r.floor_offset_rms_v);
    j["floor_drift_dph"] = JsonNumber(r.floor_drift_dph);
    j["expected_after"] = {{"offset_rms_v", JsonNumber(r.expected_after_offset_rms_v)},
                           {"rate_rms_dps", JsonNumber(r.expected_after_rate_rms_dps)},
                           {"prediction_rms_v", JsonNumber(r.prediction_rms_v)},
                           {"prediction_rms_dps", JsonNumber(r.prediction_rms_dps)}};
    j["transfer"] = {{"model_rms_v", JsonNumber(r.transfer_model_rms_v)},
                     {"truth_rms_v", JsonNumber(r.transfer_truth_rms_v)},
                     {"ratio", JsonNumber(r.transfer_ratio)},
                     {"miss_fraction", JsonNumber(r.transfer_miss_fraction)},
                     {"term", r.transfer_term},
                     {"term_rms_v", JsonNumber(r.transfer_term_rms_v)},
                     {"flagged", r.transfer_flagged}};
    j["residual_all_rms_v"] = JsonNumber(r.residual_all_rms_v);
    j["residual_all_extended_rms_v"] = JsonNumber(r.residual_all_extended_rms_v);
    j["sensitivity"] = {{"rel_rms_before", JsonNumber(r.sens_rel_rms_before)},
                        {"rel_rms_after", JsonNumber(r.sens_rel_rms_after)},
                        {"chi2_dof_before", JsonNumber(r.sens_chi2_dof_before)},
                        {"chi2_dof_after", JsonNumber(r.sens_chi2_dof_after)},
                        {"points", r.n_sensitivity_points}};
    j["bin_s"] = r.bin_s;
    j["bins"] = r.n_bins;
    j["holdout_bins"] = r.n_holdout_bins;
    j["train_bins"] = r.n_train_bins;
    j["holdout_blocks"] = r.n_holdout_blocks;
    j["heldout_gain"] = {{"mean_v2", JsonNumber(r.heldout_gain_v2)},
                         {"slope", JsonNumber(r.heldout_slope)},
                         {"z", JsonNumber(r.heldout_gain_z)}};
    j["unconfirmed"] = r.unconfirmed;
    j["plateaus"] = r.n_plateaus;
    j["power_on"] = r.power_on_source;
    j["could_not_test"] = r.could_not_test;
    j["notes"] = r.notes;
    if (r.extended_offset) j["extended_offset"] = model::ToJson(*r.extended_offset);
    if (r.extended_sensitivity) j["extended_sensitivity"] = model::ToJson(*r.extended_sensitivity);
    return j;
}

nlohmann::json ToJson(const std::vector<SensorResult>& results) {
    nlohmann::json s = nlohmann::json::array();
    for (const SensorResult& r : results) s.push_back(ToJson(r));
    return {{"sensors", s}};
}

namespace {

std::string FormatBeyond(const SensorResult& r) {
    std::string out = "  outcome: " + std::string(ToString(r.outcome)) + " (held-out residual " +
                      text::SigOrDash(r.heldout_residual_rms_v, 3) + " V, floor bound " +
                      text::SigOrDash(r.floor_bound_rms_v, 3) + " V, ratio " +
                      text::SigOrDash(r.excess_ratio, 3) + ")\n";
    out += "  thresholds from the run: slow noise k " + text::SigOrDash(r.slow_noise_k, 3) +
           (r.slow_noise_measured ? " (measured: " : " (") + r.noise_note + "); over " +
           std::to_string(r.n_surrogates) + " surrogates of that noise: features " +
           text::SigOrDash(r.feature_null_threshold, 3) + ", windows " +
           text::SigOrDash(r.window_null_threshold, 3) +
           " (standardised); false-positive rate claimed " +
           text::SigOrDash(100.0 * r.claimed_false_positive_rate, 2) + " %\n";
    for (const WindowExcess& w : r.windows_above)
        out += "  far from the floor: " + w.where + ": " + text::SigOrDash(w.rms_v, 3) +
               " V RMS where the noise leaves " + text::SigOrDash(w.expected_rms_v, 3) +
               " V (standardised " + text::SigOrDash(w.z, 3) + ", " + std::to_string(w.n) +
               " bins)\n";
    for (const std::string& a : r.ambiguities) out += "  ambiguous: " + a + "\n";
    if (!r.features.empty()) {
        out += text::Printf("  %-20s %-20s %7s %8s %8s %11s  %s\n", "beyond the list", "channel",
                            "corr", "heldout_z", "null_z", "after_v", "explains held-out");
    }
    for (const FeatureResult& f : r.features) {
        out += text::Printf(
            "  %-20s %-20s %7s %8s %8s %11s  %s  (%s)\n", f.feature.c_str(), f.channel.c_str(),
            text::SigOrDash(f.corr, 2).c_str(), text::SigOrDash(f.heldout_z, 3).c_str(),
            text::SigOrDash(f.null_z, 3).c_str(), text::SigOrDash(f.heldout_after_rms_v, 3).c_str(),
            f.explains_heldout ? "yes" : "no", f.detail.c_str());
    }
    const ResidualDiagnostics& d = r.residual;
    if (std::isfinite(d.rms_v)) {
        out += text::Printf(
            "  residual: RMS %s V, lag-1 autocorrelation %s, trend %s V/h (%s sigma), "
            "periodogram peak %s s amplitude %s V (%s x median power)\n",
            text::SigOrDash(d.rms_v, 3).c_str(), text::SigOrDash(d.lag1_autocorr, 2).c_str(),
            text::SigOrDash(d.trend_v_per_h, 3).c_str(), text::SigOrDash(d.trend_z, 2).c_str(),
            text::SigOrDash(d.period_s, 3).c_str(),
            text::SigOrDash(d.period_amplitude_v, 3).c_str(),
            text::SigOrDash(d.period_power_ratio, 2).c_str());
        out += text::Printf(
            "  residual largest at %s..%s s (%s V RMS) and at %s..%s degC (%s V RMS)\n",
            text::SigOrDash(d.worst_time.lo, 4).c_str(),
            text::SigOrDash(d.worst_time.hi, 4).c_str(),
            text::SigOrDash(d.worst_time.rms_v, 3).c_str(),
            text::SigOrDash(d.worst_temp.lo, 3).c_str(),
            text::SigOrDash(d.worst_temp.hi, 3).c_str(),
            text::SigOrDash(d.worst_temp.rms_v, 3).c_str());
    }
    for (const std::string& s : r.not_attributed) out += "  not attributed: " + s + "\n";
    for (const std::string& s : r.edges) out += "  at the edge of its search: " + s + "\n";
    for (const std::string& s : r.absent_channels) out += "  channel absent: " + s + "\n";
    for (const std::string& s : r.to_test) out += "  to test " + s + "\n";
    return out;
}

}  // namespace

std::string FormatReport(const SensorResult& r) {
    std::string out = "sensor " + r.sensor_id + ": " + r.verdict + "\n";
    out += text::Printf("  %-13s %-14s %10s %9s  %s\n", "candidate", "term", "z2", "cv_gain",
                        "decision");
    for (const CandidateResult& c : r.candidates) {
        out += text::Printf("  %-13s %-14s %10s %9s  %s\n", c.effect.c_str(), c.term.c_str(),
                            text::SigOrDash(c.z2, 3).c_str(), text::SigOrDash(c.cv_gain, 2).c_str(),
                            ToString(c.decision));
        if (!c.note.empty() && c.decision != Decision::kRejected) out += "      " + c.note + "\n";
    }
    for (const AddedEffect& a : r.added) {
        out += text::Printf("  added %-12s %-14s %12.5g +- %-10.3g %s", a.effect.c_str(),
                            a.term.c_str(), a.coefficient, a.stderr_, a.unit.c_str());
        out += std::isfinite(a.param) ? "  (parameter " + text::Sig(a.param, 4) + " +- " +
                                            text::SigOrDash(a.param_stderr, 2) + ")\n"
                                      : std::string("\n");
    }
    if (!r.unconfirmed.empty() || std::isfinite(r.heldout_gain_z)) {
        out += text::Printf(
            "  held-out check of the chosen terms: prediction slope %s (%s standard "
            "errors), squared error drop %s V^2\n",
            text::SigOrDash(r.heldout_slope, 3).c_str(),
            text::SigOrDash(r.heldout_gain_z, 3).c_str(),
            text::SigOrDash(r.heldout_gain_v2, 3).c_str());
    }
    out += text::Printf("  %-22s %14s %14s %12s\n", "held-out bins", "offset_rms_v", "rate_rms_dps",
                        "drift_dph");
    out += text::Printf("  %-22s %14s %14s %12s\n", "before (declared)",
                        text::SigOrDash(r.error_before.offset_rms_v, 3).c_str(),
                        text::SigOrDash(r.error_before.rate_rms_dps, 3).c_str(),
                        text::SigOrDash(r.error_before.drift_dph, 3).c_str());
    out += text::Printf("  %-22s %14s %14s %12s\n", "after (extended)",
                        text::SigOrDash(r.error_after.offset_rms_v, 3).c_str(),
                        text::SigOrDash(r.error_after.rate_rms_dps, 3).c_str(),
                        text::SigOrDash(r.error_after.drift_dph, 3).c_str());
    if (std::isfinite(r.expected_after_offset_rms_v)) {
        out += text::Printf("  %-22s %14s %14s %12s\n", "after expected (fit)",
                            text::SigOrDash(r.expected_after_offset_rms_v, 3).c_str(),
                            text::SigOrDash(r.expected_after_rate_rms_dps, 3).c_str(), "");
    }
    if (std::isfinite(r.transfer_ratio))
        out += "  another run (transfer check, the model taken as right): " +
               text::Sig(r.transfer_ratio, 3) + "x the true model's error expected, " +
               text::Sig(100.0 * r.transfer_miss_fraction, 2) +
               " % of surrogate runs beyond the transfer criterion; coefficients' part " +
               text::SigOrDash(r.transfer_model_rms_v, 3) + " V, truth's error " +
               text::SigOrDash(r.transfer_truth_rms_v, 3) + " V, most from " + r.transfer_term +
               "\n";
    out += text::Printf("  %-22s %14s %14s %12s\n", "floor (bin scatter)",
                        text::SigOrDash(r.floor_offset_rms_v, 3).c_str(),
                        text::SigOrDash(r.floor_rate_rms_dps, 3).c_str(),
                        text::SigOrDash(r.floor_drift_dph, 3).c_str());
    out += FormatBeyond(r);
    out += "  power-on: " + r.power_on_source + "\n";
    for (const std::string& s : r.could_not_test) out += "  could not test: " + s + "\n";
    for (const std::string& s : r.notes) out += "  note: " + s + "\n";
    return out;
}

}  // namespace gyrocal::analysis
