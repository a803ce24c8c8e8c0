#pragma once
// Live compensation of one sensor: rate_dps = (gyro_v - offset_v(T)) / sensitivity_v_per_dps(T),
// angle_deg = trapezoid integral of rate_dps over the samples' utime.
//
// State machine: no coefficients -> samples are "uncompensated" (no output). SetCoefficients
// validates a whole set first (known terms, consistent arrays, finite values, a sensitivity that
// keeps one sign and |S| > 0 across the valid range) and only then replaces the active set, so a
// sample is always computed with one complete set (the swap happens between samples). The angle
// restarts at 0 with the first sample under a new set: an angle mixing two calibrations would
// mean neither. An identical set (same source, id and coefficients, e.g. the fitter's repeat on
// RUN_EVENT stop) is not a new set and does not restart the angle.
// Inputs of extended models: dTdt and heating come from TempRateEstimator, supply_v from the
// sample, direction = sign(gyro_v - offset_v) (for a direction-dependent scale factor). A model
// needing an input the stream does not have (e.g. warmup without a power-on time) gives NaN, which
// is reported as not computable rather than published.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "model/convert.hpp"
#include "temp_rate.hpp"

namespace gyrocal::compensate {

struct CompensatorOptions {
    // Outside the calibrated range: extrapolate, flagged (compensator_main.cpp says why, with the
    // benchmark's figures: a clipped quadratic stops following the unit's curvature). kClip is for
    // models that must not be trusted outside their range.
    model::RangePolicy range_policy = model::RangePolicy::kExtrapolate;
    double temp_rate_window_s = 10.0;  // [s] see temp_rate.hpp
    static CompensatorOptions Defaults() { return {}; }
};

struct Sample {
    int64_t utime = 0;                  // [us]
    int64_t seq = 0;                    // [count]
    double gyro_v = 0.0;                // [V]
    double temp_c = 0.0;                // [degC]
    double supply_v = model::kUnknown;  // [V] NaN when not measured
};

struct Compensated {
    double rate_dps = 0.0;
    double angle_deg = 0.0;
    double rate_stderr_dps =
        model::kUnknown;  // from the coefficient covariances (calibration only)
    int64_t coeff_set_id = -1;
    model::RangeFlag range = model::RangeFlag::kInRange;
};

enum class SetOutcome { kApplied, kDuplicate, kRejected };
enum class ApplyStatus { kOk, kNoCoefficients, kOutOfOrder, kNonFinite, kNotComputable };
const char* ToString(ApplyStatus status);

struct SetResult {
    SetOutcome outcome = SetOutcome::kRejected;
    std::string detail;  // why rejected
};

struct ApplyResult {
    ApplyStatus status = ApplyStatus::kOk;
    Compensated out;     // valid when status == kOk
    std::string detail;  // why not
};

class SensorCompensator {
public:
    explicit SensorCompensator(CompensatorOptions options = CompensatorOptions::Defaults());

    SetResult SetCoefficients(const model::CoeffSet& set);
    ApplyResult Apply(const Sample& sample);

    bool has_coefficients() const { return active_ != nullptr; }
    int64_t coeff_set_id() const { return active_ ? active_->set.coeff_set_id : -1; }

private:
    struct Active {
        model::CoeffSet set;
        model::Evaluator offset;
        model::Evaluator sensitivity;
    };
    CompensatorOptions options_;
    std::shared_ptr<const Active> active_;
    TempRateEstimator temp_rate_;
    bool has_last_ = false;
    int64_t last_utime_ = 0;
    bool integrating_ = false;  // false until the first sample under the active set
    double last_rate_dps_ = 0.0;
    double angle_deg_ = 0.0;
};

// Empty when the sensitivity model is usable for division across its valid range.
std::string SensitivityProblem(const model::Evaluator& sensitivity);

}  // namespace gyrocal::compensate
