#pragma once
// Benchmark support (gyrocal_bench_verdict): one run of a scenario on a simulator, judged against
// the truth (verdict_scenarios.hpp), and the printed tables.
#include <cstdint>
#include <string>
#include <vector>

#include "tests/bench/analysis/verdict_scenarios.hpp"

namespace gyrocal::bench {

struct EffectSize {
    std::string effect;
    double ratio = 0;  // size over the floor (see bench_verdict.cpp)
    bool named = false;
};

struct RunFigures {
    std::string scenario, group, outcome, headline, category;
    std::string evidence;  // what made the outcome flag something: bound, feature, window
    std::vector<EffectSize> listed;
    double outside_ratio = 0;    // the outside effects' size over the floor
    bool outside_named = false;  // a static temperature shape named temp_cubic or temp_knot
    std::vector<std::string> added;
    bool wrong = false;
    double heldout_ratio = NAN, declared_ratio = NAN;  // extended / declared over the true model
    bool flagged = false;  // the outcome says something is left (partly/unexplained/ambiguous/
                           // not testable)
    // A single power-on exponential: truth and what was named (NaN when not named).
    double warm_v = NAN, warm_tau_s = NAN, got_v = NAN, got_v_se = NAN, got_tau = NAN,
           got_tau_se = NAN;
    double floor_v = NAN, seconds = 0;
    // VERDICT_VERBOSE's diagnosis of a run (the figures behind its held-out ratio): the analysis'
    // own predictions of its error against what the held-out run gave.
    std::string diagnosis;
};

RunFigures RunOne(Simulator sim, const Scenario& scenario, uint64_t seed);

void PrintSimulator(Simulator sim, const std::vector<RunFigures>& runs);

}  // namespace gyrocal::bench
