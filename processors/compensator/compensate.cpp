#include "processors/compensator/compensate.hpp"

#include <cmath>
#include <cstdio>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::compensator {

namespace {

constexpr text::NameTable<ApplyStatus, 5> kApplyStatusNames{
    {{ApplyStatus::kOk, "ok"},
     {ApplyStatus::kNoCoefficients, "no_coefficients"},
     {ApplyStatus::kOutOfOrder, "out_of_order"},
     {ApplyStatus::kNonFinite, "non_finite"},
     {ApplyStatus::kNotComputable, "not_computable"}}};

}  // namespace

const char* ToString(ApplyStatus s) { return text::NameOf(kApplyStatusNames, s); }

std::string ValidateSensitivity(const model::Evaluator& s) {
    // Sample the valid range densely (the models are low-order polynomials plus bounded terms),
    // at rest and at both extremes of the branch and direction terms.
    const model::Model& m = s.model();
    double sign = 0.0;
    for (int k = 0; k <= 40; ++k) {
        for (double side : {-1.0, 1.0}) {
            model::ModelInputs in = model::SteadyStateInputs(
                m, m.temp_min_c + (m.temp_max_c - m.temp_min_c) * k / 40.0);
            in.branch = in.heating = in.direction = side;
            const double v = s.Value(in, model::RangePolicy::kExtrapolate);
            if (!std::isfinite(v)) continue;  // needs an input we cannot know here; per sample
            if (v == 0.0 || (sign != 0.0 && (v > 0) != (sign > 0))) {
                return text::Printf(
                    "sensitivity is zero or changes sign at %.3g degC inside its valid "
                    "range",
                    in.temp_c);
            }
            sign = v > 0 ? 1.0 : -1.0;
        }
    }
    return "";
}

SensorCompensator::SensorCompensator(CompensatorOptions options)
    : options_(options), c_(std::make_unique<gyrocal_compensator_t>()) {
    gyrocal_compensator_init(c_.get(), nullptr, nullptr, model::CPolicy(options_.range_policy),
                             gyrocal_tracker_config_default());
}

namespace {
bool SameCoefficients(const model::Model& a, const model::Model& b) {
    return a.term_names == b.term_names && a.coeffs == b.coeffs && a.t0_c == b.t0_c &&
           a.temp_min_c == b.temp_min_c && a.temp_max_c == b.temp_max_c;
}
bool SameConfig(const gyrocal_tracker_config_t& a, const gyrocal_tracker_config_t& b) {
    return a.rate_tau_s == b.rate_tau_s && a.branch_width_c == b.branch_width_c;
}
}  // namespace

bool SensorCompensator::power_on_assumed() const { return c_->tracker.power_on_assumed != 0; }

void SensorCompensator::PowerOn(int64_t power_on_utime) {
    gyrocal_tracker_power_on(&c_->tracker, power_on_utime);
}

void SensorCompensator::Restart(const gyrocal_tracker_config_t& config) {
    // A new configuration tracks from this sample on; the power-on time is kept.
    const gyrocal_tracker_t old = c_->tracker;
    gyrocal_tracker_init(&c_->tracker, config);
    c_->tracker.has_power_on = old.has_power_on;
    c_->tracker.power_on_assumed = old.power_on_assumed;
    c_->tracker.power_on_utime = old.power_on_utime;
}

SetResult SensorCompensator::SetCoefficients(const model::CoeffSet& set) {
    if (active_ && active_->set.source == set.source &&
        active_->set.coeff_set_id == set.coeff_set_id &&
        SameCoefficients(active_->set.offset, set.offset) &&
        SameCoefficients(active_->set.sensitivity, set.sensitivity))
        return {SetOutcome::kDuplicate, ""};
    std::unique_ptr<Active> next;
    try {
        next.reset(new Active{
            set, model::Evaluator(set.offset), model::Evaluator(set.sensitivity), {}, {}, {}});
        next->config = model::TrackerConfigFor({&set.offset, &set.sensitivity});
    } catch (const model::ModelError& e) {
        return {SetOutcome::kRejected, e.what()};
    }
    if (const std::string p = ValidateSensitivity(next->sensitivity); !p.empty())
        return {SetOutcome::kRejected, p};
    next->offset_c = next->offset.CView();
    next->sensitivity_c = next->sensitivity.CView();
    SetResult result{SetOutcome::kApplied, ""};
    if (!SameConfig(next->config, c_->tracker.config)) {
        if (c_->tracker.started)
            result.detail = "trackers restarted for dT/dt time constant " +
                            std::to_string(next->config.rate_tau_s) + " s, branch width " +
                            std::to_string(next->config.branch_width_c) + " degC";
        Restart(next->config);
    }
    active_ = std::move(next);  // takes effect with the next sample
    c_->offset = &active_->offset_c;
    c_->sensitivity = &active_->sensitivity_c;
    c_->integrating = 0;
    c_->angle_deg = 0.0;
    return result;
}

ApplyResult SensorCompensator::Apply(const Sample& s) {
    ApplyResult r;
    if (!std::isfinite(s.gyro_v) || !std::isfinite(s.temp_c)) {
        r.status = ApplyStatus::kNonFinite;
        r.detail = "gyro_v and temp_c must be finite";
        return r;
    }
    if (has_last_ && s.utime <= last_utime_) {
        r.status = ApplyStatus::kOutOfOrder;
        r.detail = "utime " + std::to_string(s.utime) + " is not after the previous " +
                   std::to_string(last_utime_);
        return r;
    }
    has_last_ = true;
    last_utime_ = s.utime;
    if (!active_) {
        gyrocal_inputs_t ignored;
        gyrocal_tracker_update(&c_->tracker, s.utime, s.temp_c, s.supply_v, &ignored);
        r.status = ApplyStatus::kNoCoefficients;
        r.detail = "no coefficient set yet";
        return r;
    }
    gyrocal_rate_t rate;
    if (!gyrocal_compensate(c_.get(), s.utime, s.gyro_v, s.temp_c, s.supply_v, &rate)) {
        r.status = ApplyStatus::kNotComputable;
        r.detail = "the model needs an input this sample stream does not provide";
        return r;
    }
    r.out.rate_dps = rate.rate_dps;
    r.out.angle_deg = rate.angle_deg;
    r.out.coeff_set_id = active_->set.coeff_set_id;
    r.out.range = static_cast<model::RangeFlag>(rate.range_flag);
    r.out.inputs = model::ModelInputs(rate.inputs);
    // First-order propagation: d rate = -(d off)/S - rate (d S)/S, offset and sensitivity fits
    // independent.
    const model::RangePolicy p = options_.range_policy;
    const double var_off = active_->offset.Evaluate(r.out.inputs, p).variance;
    const double var_sens = active_->sensitivity.Evaluate(r.out.inputs, p).variance;
    r.out.rate_stderr_dps = std::sqrt(var_off + rate.rate_dps * rate.rate_dps * var_sens) /
                            std::abs(rate.sensitivity_v_per_dps);
    return r;
}

}  // namespace gyrocal::compensator
