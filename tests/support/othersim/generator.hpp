#pragma once
// othersim's run: the timeline of the profile (ramps, dwells, turns, faults), the sample loop
// that writes the CSV, and the truth JSON. Deterministic for given options.
#include <cstdint>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/othersim/options.hpp"
#include "tests/support/othersim/physics.hpp"

namespace gyrocal::othersim {

struct DwellSpan {
    int index = 0;
    double setpoint_c = 0;     // [degC]
    double ramp_start_s = 0;   // [s] its ramp begins
    double start_s = 0;        // [s] the ramp reference reached the setpoint
    double turns_start_s = 0;  // [s] the first turn begins (= end_s when no turns)
    double end_s = 0;          // [s] the next ramp may begin
};

struct TurnSpan {
    int index = 0, dwell_index = 0;
    double start_s = 0, end_s = 0;  // [s]
    double angle_deg = 0;           // [deg] the table's move (signed)
    double slip_deg = 0;            // [deg] lost by the encoder (0: none)
    double slip_start_s = 0, slip_end_s = 0;
    Move move;
};

struct DisturbanceSpan {
    int dwell_index = 0;
    std::string sensor_id;  // "" = every unit
    double offset_v = 0, start_s = 0, end_s = 0;
};

struct Timeline {
    std::vector<DwellSpan> dwells;
    std::vector<TurnSpan> turns;
    std::vector<DisturbanceSpan> disturbances;
    double duration_s = 0;
    double start_c = 25;
    struct Ramp {
        double t0_s, t1_s, from_c, to_c;
    };
    std::vector<Ramp> ramps;

    double ReferenceAt(double t_s) const;    // [degC] the chamber controller's reference
    double TableAt(double t_s) const;        // [deg] the table's true angle
    double TableRateAt(double t_s) const;    // [deg/s]
    double EncoderLossAt(double t_s) const;  // [deg] what slips have taken from the encoder
    double DisturbanceAt(const std::string& sensor_id, double t_s) const;  // [V]
};

// Throws std::invalid_argument with Options::Validate() when the options are invalid.
Timeline BuildTimeline(const Options& o);

struct Generated {
    std::vector<UnitTruth> units;
    Timeline timeline;
    int64_t rows = 0;
};

// Writes the CSV (header + one row per unit and sample) to `csv`.
Generated Generate(const Options& o, std::ostream& csv);

// The truth: units (parameters and a 1 degC table of offset and sensitivity against die
// temperature), the timeline, the faults, the noise. Format "gyrocal-othersim-truth/1".
nlohmann::json TruthJson(const Options& o, const Generated& g);

// Writes csv_path and truth_path. Throws std::runtime_error naming a file that cannot be written.
Generated WriteRun(const Options& o, const std::string& csv_path, const std::string& truth_path);

}  // namespace gyrocal::othersim
