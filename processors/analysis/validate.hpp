#pragma once
// Validation: a stored model applied to another run of the same unit (a second chamber run, a
// ramp run), as labs verify a calibration on data it was not fitted on. Every still bin of the
// run (bins.hpp: inputs tracked from the unit's power-on as the compensators track them) is
// compared with the model; the figures are those of the analysis' held-out bins (offset RMS [V],
// rate RMS [deg/s], drift [deg/h] = |integral of the rate error| / duration, per contiguous
// stretch of still data and RMS over the stretches), against the run's own floor (the Allan
// deviation at the bin length of the residual: what white noise leaves in one bin).
// Pure: no SQLite, no LCM, no clock.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "processors/analysis/bins.hpp"
#include "processors/model/convert.hpp"

namespace gyrocal::analysis {

struct ValidationResult {
    std::string sensor_id;
    std::string model_origin;
    int n_bins = 0;
    int n_stretches = 0;
    int n_bins_outside_range = 0;  // bins outside the model's valid temperature range
    double temp_min_c = kNan, temp_max_c = kNan;  // [degC] of the validated bins
    double offset_rms_v = kNan;                   // [V]
    double rate_rms_dps = kNan;                   // [deg/s]
    double drift_dph = kNan;                      // [deg/h]
    double floor_offset_rms_v = kNan;             // [V]
    double floor_rate_rms_dps = kNan;             // [deg/s]
    double floor_drift_dph = kNan;                // [deg/h] white-noise drift of one stretch
    std::string power_on;                         // where time since power-on came from
    std::vector<std::string> notes;               // what could not be computed, and why
};

// Throws model::ModelError when the set is not usable.
ValidationResult Validate(const SensorRun& run, const model::CoeffSet& set,
                          const std::string& model_origin,
                          const BinOptions& options = BinOptions::Defaults());

nlohmann::json ToJson(const ValidationResult& r);
std::string FormatValidation(const ValidationResult& r);

}  // namespace gyrocal::analysis
