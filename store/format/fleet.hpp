#pragma once
// The fleet view (`gyrocal fleet`): per unit model, how the fitted offset and sensitivity curves
// spread across units and stations, and which units lie outside their lot's spread. Pure: the
// units' coefficient sets in, numbers, text, JSON and figures out.
//
// Each unit is represented by its newest coefficient set. Its curves are evaluated by the shared
// evaluator at steady state (db::SteadyStateValue) on a temperature grid, only inside the
// set's valid range (an extrapolated curve is not a measurement). At each temperature the lot's
// centre is the median over units and its spread the robust standard deviation 1.4826 x MAD
// (median absolute deviation): one odd unit moves neither, so it cannot hide itself by widening
// the band. A unit's deviation is z = (value - median) / spread; it is OUTSIDE the lot's spread
// when |z| > k (default 3) at some temperature where at least `min_units` units have a value.
// Per station, the median over its units of their mean z says whether one station's units sit
// apart from the others' (a station bias: its reference, its chamber, its turntable).
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "processors/plot/figure.hpp"
#include "store/db/rows.hpp"

namespace gyrocal::format {

struct FleetUnit {
    std::string sensor_id, model, station, run_id;
    int64_t coeff_row_id = 0;
    db::CoeffSetRow set;
};

// The unit model a run's configuration (runs.config_json) gives a unit: "unit_models":
// {"<sensor>": "<model>"}, else "unit_model": "<model>", else "preset": "610" as "preset 610";
// "unspecified" when none (or the JSON does not parse).
std::string UnitModelOf(const std::string& config_json, const std::string& sensor_id);

struct FleetOptions {
    std::vector<double> temps_c;  // the grid [degC]; empty: -40 to 85 in steps of 5
    double k = 3.0;               // [1] |z| above which a unit is outside the spread
    size_t min_units = 4;         // units needed at a temperature for a spread there
};

struct FleetQuantity {
    std::string name;  // "offset_v" or "sensitivity_v_per_dps"
    // Per grid temperature: units with a value, median, spread (NaN where fewer than min_units).
    std::vector<size_t> n;
    std::vector<double> median, spread;
    // values[u][t]: unit u at grid temperature t (nullopt outside its set's valid range).
    std::vector<std::vector<std::optional<double>>> values;
};

struct FleetDeviation {
    size_t unit = 0;
    std::string quantity;
    double worst_z = 0, at_temp_c = 0;  // the largest |z| (signed) and where
};

struct FleetStation {
    std::string station;
    size_t units = 0;
    double offset_median_z = 0, sensitivity_median_z = 0;  // median over its units of mean z
};

struct FleetGroup {
    std::string model;
    std::vector<double> temps_c;
    std::vector<FleetUnit> units;
    FleetQuantity offset, sensitivity;
    std::vector<FleetDeviation> outside;  // |z| > k, worst first
    std::vector<FleetStation> stations;
    bool has_spread = false;  // some temperature had min_units units and a non-zero spread
};

// One group per unit model, by model name; units in each by station, then id.
std::vector<FleetGroup> FleetSpread(std::vector<FleetUnit> units, const FleetOptions& options);

std::string FleetText(const std::vector<FleetGroup>& groups, const FleetOptions& options);
nlohmann::json FleetJson(const std::vector<FleetGroup>& groups, const FleetOptions& options);
// Two figures per model (offset, sensitivity): the band median +- k spread, the median, each
// unit's curve; the units outside drawn in red and named.
std::vector<plot::Figure> FleetFigures(const std::vector<FleetGroup>& groups,
                                       const FleetOptions& options);

}  // namespace gyrocal::format
