#pragma once
// Held-out evaluation: how well coefficient sets compensate a still unit over a temperature
// profile the calibration never saw, against the rig's truth.
//
// The record: the rig (same RigConfig, so the same units) idles lead_in_s at its start
// temperature (discarded), then the chamber ramps through `waypoints_c` at ramp_c_per_min, holds
// hold_s at the last one, and stops; the table never moves, so the true rate is 0 (the truth's
// rate is used anyway). Why a lead-in: the rig draws units and noise from ONE seed, so a record
// with the calibration's seed starts on the very noise samples the calibration averaged; idling
// past the calibration's length puts the record on noise samples no calibration drew (fresh
// noise, same units).
//
// Every coefficient set is applied by the live compensator's library (SensorCompensator, its
// default range policy: clip) to every sample of its sensor in one pass of the rig. The error
// e = rate_dps - true rate is averaged over bins of bin_s of data time: the model's error moves
// with temperature over minutes, the white rate noise (~0.5 deg/s rms per 100 Hz sample) would
// otherwise hide it; at 0.5 degC/min a 10 s bin spans 0.08 degC, so a bin mean keeps the model
// error whole while the white noise drops ~30x.
//
// The floor, per sample, is what a PERFECT model would leave on the same samples:
//   floor      = (gyro_v - offset_true(T_die)) / S_true(T_die) - true rate
// (rate noise, module LPF, ADC), and floor_meas the same with the truth evaluated at the
// MEASURED temperature minus the unit's known sensor offset: the best any model of the measured
// temperature can do (adds the temperature sensor's lag and noise). Undeclared rig effects, when
// switched on, belong to the truth: both floors subtract them as the rig reports them (at the die).
// Drift: the integrated error over the whole record (trapezoid over sample times) divided by its
// duration, in deg/h.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "processors/compensator/compensate.hpp"
#include "processors/model/convert.hpp"
#include "producers/sim/rig.hpp"

namespace gyrocal::virtual_lab {

struct HeldOutProfile {
    std::vector<double> waypoints_c = {-40.0, 85.0, 25.0};  // [degC] visited in order
    double ramp_c_per_min = 0.5;  // [degC/min] slow: the sensor lags its die by 15 s x ramp
    double hold_s = 600.0;        // [s] at the last waypoint before the record ends
    double lead_in_s = 0.0;       // [s] idle before recording (fresh noise, see above)
    double bin_s = 10.0;          // [s] error bins
    // Throws std::invalid_argument naming the field when not usable for `rig`.
    void Validate(const sim::RigConfig& rig) const;
};

// Coefficient sets to evaluate: one entry per candidate, each a set per sensor id (a sensor
// without a set in a candidate is skipped for that candidate).
using Candidate = std::map<std::string, model::CoeffSet>;

struct SensorHeldOut {
    std::string sensor_id;
    std::vector<double> t_s;             // [s] bin centre since the record's start
    std::vector<double> temp_c;          // [degC] bin mean measured temperature
    std::vector<double> die_c;           // [degC] bin mean true die temperature
    std::vector<double> floor_dps;       // [deg/s] bin mean of the perfect model's error
    std::vector<double> floor_meas_dps;  // [deg/s] same, truth at the measured temperature
    double floor_angle_deg = 0;          // [deg] integrated floor error at the end
    double floor_meas_angle_deg = 0;     // [deg]
    // Per candidate (same index as the input): bin mean error, NaN where the set was missing or
    // a sample of the bin could not be compensated; integrated error; samples not compensated.
    std::vector<std::vector<double>> err_dps;
    std::vector<double> angle_deg;
    std::vector<int64_t> not_compensated;
};

struct HeldOutResult {
    double duration_s = 0;               // [s] of the record (after the lead-in)
    double bin_s = 0;                    // [s]
    std::vector<SensorHeldOut> sensors;  // the rig's units, in order
};

// The compensator with out-of-range temperatures CLIPPED: the seed's behaviour, which the held-out
// rows are labelled by (the library's own default extrapolates).
compensator::CompensatorOptions ClippedOptions();

// Records the profile once and compensates it with every candidate. Throws on a bad profile or
// rig config, or when a candidate's set is rejected by the compensator (what() says why).
HeldOutResult EvaluateHeldOut(const sim::RigConfig& rig, const HeldOutProfile& profile,
                              const std::vector<Candidate>& candidates,
                              const compensator::CompensatorOptions& options = ClippedOptions());

// Figures of one error series (bins), NaN bins ignored.
struct Score {
    double rms_dps = 0;      // [deg/s] RMS of the bin means
    double max_in_dps = 0;   // [deg/s] max |bin mean| with the bin's temp inside [min, max]
    double max_out_dps = 0;  // [deg/s] max |bin mean| outside (0 when no bin is outside)
    double drift_dph = 0;    // [deg/h] integrated error / duration
    int bins_in = 0, bins_out = 0;
};
Score ScoreBins(const std::vector<double>& err_dps, const std::vector<double>& temp_c,
                double range_min_c, double range_max_c, double angle_deg, double duration_s);

// The truth of a unit as a coefficient set in the MEASURED temperature (t0 = 25 degC + the
// sensor's offset, so that dT equals T_die - 25 at rest), valid over [min_c, max_c] measured.
// For tests: a perfect calibration.
model::CoeffSet TruthSet(const sim::UnitTruth& unit, double min_c, double max_c);

}  // namespace gyrocal::virtual_lab
