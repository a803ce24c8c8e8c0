#pragma once
// The command line of gyrocal-othersim (main.cpp): options into othersim::Options.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "tests/support/othersim/options.hpp"

namespace gyrocal::othersim {

struct CliValues {
    std::string out, truth_out;
    std::string setpoints = "25,-10,10,30,50,70,25";
    double dwell_s = 900.0;
    bool ramp_only = false;
    std::vector<std::string> disturb, slip;
    bool no_supply = false;
};

// Registers every option on `app`, writing into `o` and `v`.
void AddOptions(CLI::App& app, Options& o, CliValues& v);
// Completes `o` from `v` (profile, faults, supply); "" when all is valid, else the error naming
// the option.
std::string Finish(Options& o, CliValues& v);
// "3:U2:0.004" (dwell 3, unit U2, 4 mV), "3:0.004" (every unit), "3:U2:0.004:100:200" (from
// 100 s into the dwell for 200 s). Throws invalid_argument.
Disturbance ParseDisturbance(const std::string& text);
// "5:2.5" (turn 5 loses 2.5 deg). Throws invalid_argument.
Slip ParseSlip(const std::string& text);

}  // namespace gyrocal::othersim
