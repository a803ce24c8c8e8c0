#pragma once
// The model inputs with their state, defined once (gyrocal_model.h): what every consumer - the
// analysis' bins, the fitter, the live compensator, `gyrocal compensate`, the exported firmware
// code - computes per sample before a model is evaluated.
//
//   temp_c              the sample's temperature
//   dtemp_dt_c_per_s    difference of two exponential averages (tau, 2 tau) of temp_c
//   branch / heating    play operator of width w on temp_c (continuous / sign-only)
//   time_since_power_s  from the power-on time (PowerOn), else from the first sample (assumed)
//   supply_v            the sample's measured supply
// A coefficient set needs ONE tracker configuration (dT/dt time constant, branch width): the one
// its terms name (TrackerConfigFor). Trackers run over every sample of the unit's stream, at rest
// or not, from power-on: the same samples give the same inputs everywhere.
#include <cstdint>
#include <vector>

#include "processors/model/gyrocal_model.h"
#include "processors/model/model.hpp"

namespace gyrocal::model {

// The configuration the terms of `models` need (dTdt(tau), dT*dTdt(tau) -> tau, heating(w) -> w,
// "heating" -> the sign-only 1 degC); defaults where they name none. Throws ModelError when two
// terms ask for different time constants or widths (one tracker per input per coefficient set).
gyrocal_tracker_config_t TrackerConfigFor(const std::vector<const Model*>& models);
gyrocal_tracker_config_t TrackerConfigFor(const Model& model);

class InputTracker {
public:
    explicit InputTracker(gyrocal_tracker_config_t config = gyrocal_tracker_config_default());

    // The unit was powered at utime [us] (a later call is a new power cycle).
    void PowerOn(int64_t power_on_utime);
    // One sample in time order; the inputs at it (direction NaN).
    ModelInputs Update(int64_t utime, double temp_c, double supply_v);

    // True when the power-on time is the first sample's (no power-on record was given).
    bool power_on_assumed() const { return state_.power_on_assumed != 0; }
    const gyrocal_tracker_config_t& config() const { return state_.config; }
    const gyrocal_tracker_t& state() const { return state_; }

private:
    gyrocal_tracker_t state_;
};

// Inputs of a unit at rest at temp_c, long after power-on, at nominal supply, neither heating nor
// cooling (branch 0), rotation direction 0: what "the model's value at T" means for a table or a
// plot. Tracked with the configuration `model` needs, so its dynamic terms contribute 0.
ModelInputs SteadyStateInputs(const Model& model, double temp_c);

}  // namespace gyrocal::model
