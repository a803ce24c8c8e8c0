#pragma once
// Test/benchmark support: one simulated unit run in-process on the rig library (gyrocal_sim),
// turned into the analysis input exactly as a recorded run would be: raw gyro + encoder samples
// through BuildSensorRun, plus the plateaus and sensitivity points that the plateau detector and
// the rotation estimator would have published (computed here the same way: plateau = the last
// plateau_window_s of each dwell; sensitivity = integral of (gyro_v - rest offset) over the move /
// encoder angle, offset from 5 s rest windows before and after). The rig's truth is returned
// beside it for the tests to check answers against; the analysis never sees it.
#include <cstdint>
#include <functional>
#include <vector>

#include "processors/analysis/run_data.hpp"
#include "producers/sim/builtin_profile.hpp"
#include "producers/sim/rig.hpp"

namespace gyrocal::analysis::testing {

// What an outside effect may depend on at each gyro sample.
struct OutsideInputs {
    double t_s = 0.0;        // [s] since the start
    double temp_c = 0.0;     // [degC] the unit's measured temperature
    double air_c = kNan;     // [degC] the chamber air as recorded (air_offset_c included)
    double table_deg = 0.0;  // [deg] the table's angle (latest encoder reading)
};

struct SimRunOptions {
    uint64_t seed = 1;
    uint64_t noise_seed = 0;  // 0 = seed's noise; another value: the same units, fresh noise
    int64_t start_utime = 0;  // [us] 0 = the rig's default start
    sim::EffectsConfig effects;
    // Start 25 degC; down, up, down, up, down: ramps in both directions through shared
    // temperatures.
    std::vector<double> setpoints_c = {-10.0, 50.0, 10.0, 70.0, 30.0};
    double dwell_s = 420.0;           // [s] at setpoint before the rotations (7 package taus)
    double rest_s = 20.0;             // [s] after each move
    double plateau_window_s = 120.0;  // [s] end of the dwell averaged as the plateau
    double ramp_c_per_min = 6.0;
    double package_tau_s = 60.0;  // fast thermal constants keep the run short
    double air_tau_s = 10.0;
    double sensor_tau_s = 0.1;  // see the tests: a slow sensor is itself a temp_rate effect
    bool record_supply = true;
    // An offset outside the rig's effect list [V] as a function of the time since the start [s],
    // added to every recorded gyro_v (slow drift, periodic disturbance, step, ...). Empty: none.
    std::function<double(double)> outside_v;
    // The same from every channel [V] (added to outside_v's).
    std::function<double(const OutsideInputs&)> outside_channels_v;
    // Added to the recorded chamber air [degC] as a function of the time since the start [s]: air
    // movement the unit's temperature sensor does not see (it lags far behind). Empty: none.
    std::function<double(double)> air_offset_c;
    bool record_air = true;  // the chamber air in the run (SensorRun::air, the database)
};

struct SimRun {
    SensorRun run;
    sim::UnitTruth truth;
    sim::RigConfig config;
    double duration_s = 0.0;
    std::vector<GyroSample> raw;  // every sample as recorded (for writing a database)
    std::vector<motion::EncoderReading> encoder;
    std::vector<PowerRecord> power;  // the unit's power-on (the rig's start)
    std::vector<AirSample> air;      // the chamber air as recorded (empty without record_air)
    // [V] per gyro sample (the order of run.samples): what the unit's true model gives at the
    // MEASURED temperature (the rig's curve at the measured temperature less the sensor's offset,
    // plus every effect's offset and the outside offsets): the best any model of the measured
    // temperature can do (virtual_lab's floor_meas, in volts).
    std::vector<double> truth_offset_v;
    std::vector<double> effect_offset_v;  // [V] the effects' and outside offsets' part of it
};

// keep_raw: also return the raw samples and encoder readings (memory: ~40 bytes per sample).
SimRun MakeSimRun(const SimRunOptions& options, bool keep_raw = false);

}  // namespace gyrocal::analysis::testing
