// AnalysisOptions validation and the decision names (analyze.hpp).
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "lcmtypes/text/names.hpp"
#include "processors/analysis/analyze.hpp"

namespace gyrocal::analysis {

namespace {

constexpr text::NameTable<Decision, 4> kDecisionNames{{{Decision::kAdded, "added"},
                                                       {Decision::kRejected, "rejected"},
                                                       {Decision::kAmbiguous, "ambiguous"},
                                                       {Decision::kNotTested, "not_tested"}}};

constexpr text::NameTable<Outcome, 6> kOutcomeNames{
    {{Outcome::kAdequate, "adequate"},
     {Outcome::kExplained, "explained"},
     {Outcome::kPartlyExplained, "partly explained"},
     {Outcome::kUnexplained, "unexplained residual"},
     {Outcome::kNotTestable, "not testable"},
     {Outcome::kAmbiguous, "ambiguous"}}};

constexpr text::NameTable<WindowStatistic, 2> kWindowStatisticNames{
    {{WindowStatistic::kStudentised, "studentised"}, {WindowStatistic::kPlugin, "plugin"}}};

}  // namespace

const char* ToString(WindowStatistic s) { return text::NameOf(kWindowStatisticNames, s); }

bool ParseWindowStatistic(const std::string& name, WindowStatistic* out) {
    const std::optional<WindowStatistic> v = text::ValueOf(kWindowStatisticNames, name);
    if (v && out) *out = *v;
    return v.has_value();
}

const char* ToString(Decision d) { return text::NameOf(kDecisionNames, d); }

const char* ToString(Outcome o) { return text::NameOf(kOutcomeNames, o); }

double AnalysisOptions::ClaimedFalsePositiveRate() const {
    return feature_fpr + window_fpr + warmup_fpr + 0.0027;
}

std::string AnalysisOptions::Validate() const {
    if (!(bins.bin_s > 0.0 && bins.bin_s <= 600.0)) return "bin_s must be in (0, 600] s";
    if (!(bins.min_fill > 0.0 && bins.min_fill <= 1.0)) return "min_fill must be in (0, 1]";
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
    if (!(min_pair_member_z2 >= 0.0 && std::isfinite(min_pair_member_z2)))
        return "min_pair_member_z2 must be finite and >= 0";
    if (!(holdout_fraction >= 0.05 && holdout_fraction <= 0.5))
        return "holdout_fraction must be in [0.05, 0.5] (one block in 2 to one in 20)";
    if (!(holdout_block_s >= 10.0 * bins.bin_s))
        return "holdout_block_s must be at least 10 bins long";
    if (!(gate_min_z >= 0.0)) return "gate_min_z must be >= 0";
    if (!(slow_noise_floor_ratio <= 10.0))
        return "slow_noise_floor_ratio must be <= 10 (negative: measured from the run)";
    if (!(min_feature_drop >= 0.0 && min_feature_drop < 1.0))
        return "min_feature_drop must be in [0, 1)";
    if (surrogates < 20 || surrogates > 10000) return "surrogates must be 20..10000";
    for (const auto& [name, v] : {std::pair<const char*, double>{"feature_fpr", feature_fpr},
                                  {"window_fpr", window_fpr},
                                  {"warmup_fpr", warmup_fpr}})
        if (!(v > 0.0 && v < 0.5)) return std::string(name) + " must be in (0, 0.5)";
    if (!(early_block_s >= bins.bin_s)) return "early_block_s must be at least one bin long";
    if (!(max_untested_fraction >= 0.0 && max_untested_fraction <= 1.0))
        return "max_untested_fraction must be in [0, 1]";
    if (!(min_effect_floor_ratio >= 0.0)) return "min_effect_floor_ratio must be >= 0";
    if (!(min_feature_floor_ratio >= 0.0)) return "min_feature_floor_ratio must be >= 0";
    if (!(max_transfer_ratio == 0.0 ||
          (max_transfer_ratio > 1.0 && std::isfinite(max_transfer_ratio))))
        return "max_transfer_ratio must be 0 (off) or finite and > 1";
    if (!(rate_tau_min_s > 0.0 && rate_tau_max_s > rate_tau_min_s))
        return "dT/dt time constant range must satisfy 0 < min < max";
    if (!(branch_width_min_c > 0.0 && branch_width_max_c > branch_width_min_c))
        return "branch width range must satisfy 0 < min < max";
    if (!(warmup_tau_min_s > 0.0 && warmup_tau_max_s > warmup_tau_min_s))
        return "warmup tau range must satisfy 0 < min < max";
    return "";
}

}  // namespace gyrocal::analysis
