#pragma once
// Test/benchmark support: one othersim unit (tests/support/othersim, an independent rig) run
// in-process through the CSV reader into the analysis input, as `gyrocal calibrate --source csv`
// would record it: raw gyro + encoder samples through BuildSensorRun, the chamber_c column as
// the chamber air. The CSV has no power-on column, so the first sample is the power-on (as the
// analysis assumes and says). Beside it, per sample, the unit's true offset at the MEASURED
// temperature (othersim's curve at the die temperature the reported one maps back to, plus its
// power-on warm-up and its outside effects): what evaluations compare a model with; the analysis
// never sees it.
#include <vector>

#include "processors/analysis/run_data.hpp"
#include "tests/support/othersim/options.hpp"

namespace gyrocal::analysis::testing {

struct OthersimRun {
    SensorRun run;
    std::vector<double> truth_offset_v;  // [V] per sample of run.samples
};

// Options with one unit (o.units is set to 1).
OthersimRun MakeOthersimRun(othersim::Options o);

}  // namespace gyrocal::analysis::testing
