#include "compensate.hpp"

#include <cmath>
#include <cstdio>

namespace gyrocal::compensate {

const char* ToString(ApplyStatus s) {
    switch (s) {
        case ApplyStatus::kOk:
            return "ok";
        case ApplyStatus::kNoCoefficients:
            return "no_coefficients";
        case ApplyStatus::kOutOfOrder:
            return "out_of_order";
        case ApplyStatus::kNonFinite:
            return "non_finite";
        case ApplyStatus::kNotComputable:
            return "not_computable";
    }
    return "?";
}

std::string SensitivityProblem(const model::Evaluator& s) {
    // Sample the valid range densely (the models are low-order polynomials plus bounded terms) with
    // the other inputs at both signs of the branch/direction terms and neutral values otherwise.
    const model::Model& m = s.model();
    double sign = 0.0;
    for (int k = 0; k <= 40; ++k) {
        for (double branch : {-1.0, 1.0}) {
            model::ModelInputs in;
            in.temp_c = m.temp_min_c + (m.temp_max_c - m.temp_min_c) * k / 40.0;
            in.dtemp_dt_c_per_s = 0.0;
            in.supply_v = model::kNominalSupplyV;
            in.heating = branch;
            in.direction = branch;
            in.time_since_power_s = 1e9;
            const double v = s.Value(in, model::RangePolicy::kExtrapolate);
            if (!std::isfinite(v))
                continue;  // needs an input we cannot know here; checked per sample
            char buf[160];
            if (v == 0.0 || (sign != 0.0 && (v > 0) != (sign > 0))) {
                std::snprintf(
                    buf, sizeof buf,
                    "sensitivity is zero or changes sign at %.3g degC inside its valid range",
                    in.temp_c);
                return buf;
            }
            sign = v > 0 ? 1.0 : -1.0;
        }
    }
    return "";
}

SensorCompensator::SensorCompensator(CompensatorOptions options)
    : options_(options), temp_rate_(options.temp_rate_window_s) {}

namespace {
bool SameCoefficients(const model::Model& a, const model::Model& b) {
    return a.term_names == b.term_names && a.coeffs == b.coeffs && a.t0_c == b.t0_c &&
           a.temp_min_c == b.temp_min_c && a.temp_max_c == b.temp_max_c;
}
}  // namespace

SetResult SensorCompensator::SetCoefficients(const model::CoeffSet& set) {
    if (active_ && active_->set.source == set.source &&
        active_->set.coeff_set_id == set.coeff_set_id &&
        SameCoefficients(active_->set.offset, set.offset) &&
        SameCoefficients(active_->set.sensitivity, set.sensitivity))
        return {SetOutcome::kDuplicate, ""};
    std::shared_ptr<const Active> next;
    try {
        next = std::make_shared<const Active>(
            Active{set, model::Evaluator(set.offset), model::Evaluator(set.sensitivity)});
    } catch (const model::ModelError& e) {
        return {SetOutcome::kRejected, e.what()};
    }
    if (const std::string p = SensitivityProblem(next->sensitivity); !p.empty())
        return {SetOutcome::kRejected, p};
    active_ = std::move(next);  // takes effect with the next sample
    integrating_ = false;
    angle_deg_ = 0.0;
    return {SetOutcome::kApplied, ""};
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
    const double dt_s = has_last_ ? 1e-6 * static_cast<double>(s.utime - last_utime_) : 0.0;
    has_last_ = true;
    last_utime_ = s.utime;
    temp_rate_.Add(s.utime, s.temp_c);
    if (!active_) {
        r.status = ApplyStatus::kNoCoefficients;
        r.detail = "no coefficient set yet";
        return r;
    }
    model::ModelInputs in;
    in.temp_c = s.temp_c;
    in.supply_v = s.supply_v;
    in.dtemp_dt_c_per_s = temp_rate_.rate_c_per_s();
    in.heating = temp_rate_.heating();
    const model::Evaluation off = active_->offset.Evaluate(in, options_.range_policy);
    in.direction = s.gyro_v - off.value >= 0 ? 1.0 : -1.0;
    const model::Evaluation sens = active_->sensitivity.Evaluate(in, options_.range_policy);
    const double rate = (s.gyro_v - off.value) / sens.value;
    if (!std::isfinite(rate)) {
        r.status = ApplyStatus::kNotComputable;
        r.detail =
            "the model needs an input this sample stream does not provide (or is not known yet)";
        integrating_ = false;  // do not integrate across the hole
        return r;
    }
    if (integrating_) angle_deg_ += 0.5 * (last_rate_dps_ + rate) * dt_s;
    integrating_ = true;
    last_rate_dps_ = rate;
    r.out.rate_dps = rate;
    r.out.angle_deg = angle_deg_;
    r.out.coeff_set_id = active_->set.coeff_set_id;
    r.out.range = off.range != model::RangeFlag::kInRange ? off.range : sens.range;
    // First-order propagation: d rate = -(d off)/S - rate (d S)/S, offset and sensitivity fits
    // independent.
    r.out.rate_stderr_dps =
        std::sqrt(off.variance + rate * rate * sens.variance) / std::abs(sens.value);
    return r;
}

}  // namespace gyrocal::compensate
