#pragma once
// Benchmark support (gyrocal_bench_verdict): the scenarios - what is switched on in one run of a
// simulator, drawn at random sizes per seed - and the truth the benchmark judges the analysis by.
// Groups: clean; each listed effect (the analysis' candidates' shapes); effects outside the list
// (shapes no candidate and, for most, no generic feature has: |dT/dt|, temperature acceleration,
// random bias steps, a sawtooth, a slow exogenous wander, and the older drift); static temperature
// shapes beyond the cubic that no candidate has in their form (a hot-end exponential bend,
// (T-25)^4), which the spline knot (temp_knot) may describe; power-on transients; a one-time shift
// after an event; combinations (listed + outside, two listed, transient + listed).
// On the project's rig a run's first listed effect is the rig's own (sim::SetEffect, its
// physics: on the die temperature, the true supply, ...), further ones are added after the
// simulator; on othersim every effect is added after it (verdict_effects.hpp).
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "producers/sim/config.hpp"
#include "tests/bench/analysis/verdict_effects.hpp"

namespace gyrocal::bench {

enum class Simulator { kRig, kOthersim };
const char* Name(Simulator s);

struct ListedPart {
    std::string effect;    // as the analysis names it: temp_rate, hysteresis, ...
    PostHoc post;          // the part added after the simulator (unused for the rig's own)
    bool rig_own = false;  // the rig's effect (sim_effects) instead of `post`
};

struct Draw {
    std::vector<ListedPart> listed;
    sim::EffectsConfig sim_effects;  // the rig's own effect, when a listed part is rig_own
    PostHoc outside;                 // everything outside the list
    bool has_outside = false;
    // Names that are right for the outside part. A static function of the temperature (a hot-end
    // bend, (T-25)^4): the analysis' spline knot beyond its cubic (temp_knot) is a generic static
    // temperature shape, so temp_cubic and temp_knot. A rate that leads the thermometer: temp_rate
    // (the right physics seen through a lagging thermometer).
    std::vector<std::string> outside_right_names;
    double warmup_v = 0, warmup_tau_s = 0;  // a single power-on exponential (listed), else 0
    // othersim's temperature line lags its die by 1 s: a real, small temp_rate in every run of it,
    // "clean" included. Off: the temperature read is the die's (the control for the clean rate).
    bool temp_lag_off = false;
};

struct Scenario {
    std::string name, group;  // group: clean, listed, outside, transient, shift, combination
    Draw (*make)(Simulator, std::mt19937_64&);
    bool othersim_only = false;  // meaningless on the rig (its sensor lags 0.1 s: no lag to remove)
};

const std::vector<Scenario>& Scenarios();

}  // namespace gyrocal::bench
