#pragma once
// Live compensation of one sensor: rate_dps = (gyro_v - offset_v(inputs)) /
// sensitivity_v_per_dps(inputs), angle_deg = trapezoid integral of rate_dps over the samples'
// utime. The arithmetic per sample is gyrocal_model.h's gyrocal_compensate (the exported firmware
// code runs the same), so the live compensator, `gyrocal compensate` and the firmware agree
// sample for sample when they see the same samples from the same start.
//
// Inputs (model/inputs.hpp): tracked over every sample from the first one the compensator sees,
// whether a set is in force or not, with the tracker configuration the active set's terms name;
// time since power-on from PowerOn (a POWER_<id> record) or else from the first sample (then
// flagged as assumed: a model with a warm-up term is evaluated, and the STATUS says on what).
//
// State machine: no coefficients -> samples are "uncompensated" (no output). SetCoefficients
// validates a whole set first (known terms, consistent arrays, finite values, one tracker
// configuration, a sensitivity that keeps one sign and |S| > 0 across the valid range) and only
// then replaces the active set, so a sample is always computed with one complete set (the swap
// happens between samples). The angle restarts at 0 with the first sample under a new set: an
// angle mixing two calibrations would mean neither. An identical set (same source, id and
// coefficients, e.g. the fitter's repeat on RUN_EVENT stop) is not a new set. A set whose terms
// need another tracker configuration (another dT/dt time constant or branch width) restarts those
// trackers at that sample: dT/dt from 0, the branch unknown (0) until the temperature has moved
// half the width (SetResult::detail says so). A model needing an input the stream does not have
// (e.g. supply without supply_v) gives NaN, reported as not computable rather than published.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "processors/motion/gyro_sample.hpp"

namespace gyrocal::compensator {

struct CompensatorOptions {
    // Outside the calibrated range: extrapolate, flagged (the one out-of-range rule is stated in
    // processors/model/model.hpp). kClip is for models that must not be trusted outside their
    // range.
    model::RangePolicy range_policy = model::RangePolicy::kExtrapolate;
    static CompensatorOptions Defaults() { return {}; }
};

// A gyro sample (the one struct, motion/gyro_sample.hpp) and its one conversion from a gyro
// reading.
using Sample = motion::GyroSample;
template <class Gyro>
Sample SampleOf(const Gyro& g) {
    return motion::GyroSampleOf(g);
}

struct Compensated {
    double rate_dps = 0.0;
    double angle_deg = 0.0;
    double rate_stderr_dps =
        model::kUnknown;  // from the coefficient covariances (calibration only)
    int64_t coeff_set_id = -1;
    model::RangeFlag range = model::RangeFlag::kInRange;
    model::ModelInputs inputs;  // what the models were evaluated with
};

enum class SetOutcome { kApplied, kDuplicate, kRejected };
enum class ApplyStatus { kOk, kNoCoefficients, kOutOfOrder, kNonFinite, kNotComputable };
const char* ToString(ApplyStatus status);

struct SetResult {
    SetOutcome outcome = SetOutcome::kRejected;
    std::string detail;  // why rejected; for an applied set, trackers restarted (or "")
};

struct ApplyResult {
    ApplyStatus status = ApplyStatus::kOk;
    Compensated out;     // valid when status == kOk
    std::string detail;  // why not
};

class SensorCompensator {
public:
    explicit SensorCompensator(CompensatorOptions options = CompensatorOptions::Defaults());
    // The compensator holds pointers into its own active set.
    SensorCompensator(const SensorCompensator&) = delete;
    SensorCompensator& operator=(const SensorCompensator&) = delete;
    SensorCompensator(SensorCompensator&&) = default;

    SetResult SetCoefficients(const model::CoeffSet& set);
    // The unit was powered at power_on_utime [us] (a newer value: a new power cycle).
    void PowerOn(int64_t power_on_utime);
    ApplyResult Apply(const Sample& sample);

    bool has_coefficients() const { return active_ != nullptr; }
    int64_t coeff_set_id() const { return active_ ? active_->set.coeff_set_id : -1; }
    bool power_on_assumed() const;

private:
    struct Active {
        model::CoeffSet set;
        model::Evaluator offset;
        model::Evaluator sensitivity;
        gyrocal_model_t offset_c, sensitivity_c;  // views into the two evaluators
        gyrocal_tracker_config_t config;
    };
    void Restart(const gyrocal_tracker_config_t& config);

    CompensatorOptions options_;
    std::unique_ptr<Active> active_;
    std::unique_ptr<gyrocal_compensator_t> c_;  // tracker and angle (stable address)
    bool has_last_ = false;
    int64_t last_utime_ = 0;
};

// Empty when the sensitivity model is usable for division across its valid range.
std::string ValidateSensitivity(const model::Evaluator& sensitivity);

}  // namespace gyrocal::compensator
