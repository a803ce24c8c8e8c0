#include "tests/bench/analysis/verdict_scenarios.hpp"

#include <cmath>

namespace gyrocal::bench {

namespace {

// Log-uniform in [lo, hi], random sign when `signed_`.
double LogU(std::mt19937_64& r, double lo, double hi, bool signed_ = true) {
    const double v = lo * std::pow(hi / lo, std::uniform_real_distribution<double>(0, 1)(r));
    return signed_ && std::uniform_int_distribution<int>(0, 1)(r) ? -v : v;
}
double U(std::mt19937_64& r, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(r);
}

// One listed effect at a random size (log-uniform: sizes from about the 10 s-bin floor of ~0.1 mV
// to 30x it once projected out of the declared quadratic, most above 5x). On the rig, `own` uses
// the rig's physics.
ListedPart Listed(const std::string& e, Simulator s, bool own, std::mt19937_64& r, Draw& d) {
    ListedPart p;
    p.effect = e;
    p.rig_own = own && s == Simulator::kRig;
    if (e == "temp_rate") {
        const double k = LogU(r, 4e-5, 1e-3);  // [V/(degC/min)]
        if (p.rig_own) sim::SetEffect(d.sim_effects, "temp_rate", k);
        p.post.rate_v_per_c_per_s = k * 60.0;
    } else if (e == "hysteresis") {
        const double v = LogU(r, 4e-4, 8e-3, false);  // branches this far apart [V]
        if (p.rig_own) sim::SetEffect(d.sim_effects, "hysteresis", v);
        p.post.branch_v = 0.5 * v;
        p.post.branch_width_c = U(r, 1.0, 4.0);
    } else if (e == "temp_cubic") {
        const double c = LogU(r, 6e-9, 1.5e-7);
        if (p.rig_own) sim::SetEffect(d.sim_effects, "temp_cubic", c);
        p.post.cubic_v_per_c3 = c;
    } else if (e == "supply") {
        const double k = LogU(r, 0.01, 0.4);
        if (p.rig_own) sim::SetEffect(d.sim_effects, "supply", k);
        p.post.supply_v_per_v = k;
    } else if (e == "warmup") {
        d.warmup_v = LogU(r, 1e-3, 1.5e-2);
        d.warmup_tau_s = U(r, 120.0, 600.0);
        if (p.rig_own) {
            sim::SetEffect(d.sim_effects, "warmup", d.warmup_v);
            sim::SetEffect(d.sim_effects, "warmup_tau_s", d.warmup_tau_s);
        }
        p.post.warmup_v = d.warmup_v;
        p.post.warmup_tau_s = d.warmup_tau_s;
    }
    return p;
}

Draw Clean(Simulator, std::mt19937_64&) { return {}; }

Draw CleanNoLag(Simulator, std::mt19937_64&) {
    Draw d;
    d.temp_lag_off = true;
    return d;
}

template <const char* kEffect>
Draw One(Simulator s, std::mt19937_64& r) {
    Draw d;
    d.listed.push_back(Listed(kEffect, s, true, r, d));
    return d;
}

Draw Out(std::mt19937_64& r, void (*set)(PostHoc&, std::mt19937_64&)) {
    Draw d;
    d.has_outside = true;
    d.outside.wander_seed = r();
    set(d.outside, r);
    return d;
}

void AbsRate(PostHoc& p, std::mt19937_64& r) { p.abs_rate_v_per_c_per_s = LogU(r, 0.005, 0.08); }
void Accel(PostHoc& p, std::mt19937_64& r) { p.accel_v_per_c_per_s2 = LogU(r, 0.3, 10.0); }
void Steps(PostHoc& p, std::mt19937_64& r) {
    for (int k = 0; k < 3; ++k) p.steps.push_back({U(r, 300.0, 4500.0), LogU(r, 2e-4, 2e-3)});
}
void Saw(PostHoc& p, std::mt19937_64& r) {
    p.saw_v = LogU(r, 6e-4, 8e-3), p.saw_s = U(r, 500, 1500);
}
void Wander(PostHoc& p, std::mt19937_64& r) {
    p.wander_v = LogU(r, 4e-4, 5e-3, false), p.wander_tau_s = U(r, 1000, 3000);
}
void Bend(PostHoc& p, std::mt19937_64& r) {
    p.hot_bend_v = LogU(r, 1e-3, 1.5e-2), p.hot_bend_c = U(r, 6, 15);
}
void Quartic(PostHoc& p, std::mt19937_64& r) { p.quartic_v_per_c4 = LogU(r, 4e-10, 6e-9); }
// The listed rate's sizes, on the centred difference: what a unit whose thermometer lags its die
// by 15 s shows.
void LeadRate(PostHoc& p, std::mt19937_64& r) {
    p.lead_rate_v_per_c_per_s = LogU(r, 4e-5, 1e-3) * 60;
}
void Drift(PostHoc& p, std::mt19937_64& r) { p.drift_v_per_h = LogU(r, 3e-4, 4e-3); }
void Shift(PostHoc& p, std::mt19937_64& r) {
    p.steps.push_back({U(r, 1000.0, 4000.0), LogU(r, 3e-4, 3e-3)});
}
void TwoExp(PostHoc& p, std::mt19937_64& r) {
    p.warmup2_v = LogU(r, 1e-3, 4e-3), p.warmup2_tau_s = U(r, 60, 150);
    p.steps.clear();
}

Draw OAbsRate(Simulator, std::mt19937_64& r) { return Out(r, AbsRate); }
Draw OAccel(Simulator, std::mt19937_64& r) { return Out(r, Accel); }
Draw OSteps(Simulator, std::mt19937_64& r) { return Out(r, Steps); }
Draw OSaw(Simulator, std::mt19937_64& r) { return Out(r, Saw); }
Draw OWander(Simulator, std::mt19937_64& r) { return Out(r, Wander); }
Draw StaticTemp(Draw d) {
    d.outside_right_names = {"temp_cubic", "temp_knot"};
    return d;
}
Draw OBend(Simulator, std::mt19937_64& r) { return StaticTemp(Out(r, Bend)); }
Draw OQuartic(Simulator, std::mt19937_64& r) { return StaticTemp(Out(r, Quartic)); }
Draw ODrift(Simulator, std::mt19937_64& r) { return Out(r, Drift); }
Draw OShift(Simulator, std::mt19937_64& r) { return Out(r, Shift); }
Draw OLeadRate(Simulator, std::mt19937_64& r) {
    Draw d = Out(r, LeadRate);
    d.outside_right_names = {"temp_rate"};
    return d;
}

// Two power-on exponentials (a fast one outside the list, the warm-up listed): a transient of
// another shape than the candidate's.
Draw TwoTransients(Simulator s, std::mt19937_64& r) {
    Draw d = Out(r, TwoExp);
    d.listed.push_back(Listed("warmup", s, true, r, d));
    d.warmup_v = 0;  // not a single exponential: no amplitude/tau check
    return d;
}

template <const char* kA, const char* kB>
Draw Two(Simulator s, std::mt19937_64& r) {
    Draw d;
    d.listed.push_back(Listed(kA, s, true, r, d));
    d.listed.push_back(Listed(kB, s, false, r, d));
    return d;
}

template <const char* kA>
Draw ListedAndDrift(Simulator s, std::mt19937_64& r) {
    Draw d = Out(r, Drift);
    d.listed.push_back(Listed(kA, s, true, r, d));
    return d;
}

template <const char* kA>
Draw ListedAndSaw(Simulator s, std::mt19937_64& r) {
    Draw d = Out(r, Saw);
    d.listed.push_back(Listed(kA, s, true, r, d));
    return d;
}

constexpr char kTempRate[] = "temp_rate", kHyst[] = "hysteresis", kCubic[] = "temp_cubic",
               kSupply[] = "supply", kWarmup[] = "warmup";

}  // namespace

const char* Name(Simulator s) { return s == Simulator::kRig ? "rig" : "othersim"; }

const std::vector<Scenario>& Scenarios() {
    static const std::vector<Scenario> s = {
        {"clean", "clean", Clean},
        {"temp_rate", "listed", One<kTempRate>},
        {"hysteresis", "listed", One<kHyst>},
        {"temp_cubic", "listed", One<kCubic>},
        {"supply", "listed", One<kSupply>},
        {"|dT/dt| offset", "outside", OAbsRate},
        {"d2T/dt2 offset", "outside", OAccel},
        {"3 random bias steps", "outside", OSteps},
        {"sawtooth", "outside", OSaw},
        {"exogenous wander", "outside", OWander},
        {"hot-end exp bend", "static shape", OBend},
        {"(T-25)^4", "static shape", OQuartic},
        {"linear drift", "outside", ODrift},
        {"warm-up 120-600 s", "transient", One<kWarmup>},
        {"warm-up + fast exp", "transient", TwoTransients},
        {"one-time shift", "shift", OShift},
        {"supply + drift", "combination", ListedAndDrift<kSupply>},
        {"hysteresis + sawtooth", "combination", ListedAndSaw<kHyst>},
        {"temp_rate + supply", "combination", Two<kTempRate, kSupply>},
        {"hysteresis + temp_cubic", "combination", Two<kHyst, kCubic>},
        {"warm-up + supply", "combination", Two<kWarmup, kSupply>},
        // Last, so that the seeds of the scenarios above stay what they were.
        {"clean, thermometer lag off", "clean", CleanNoLag, true},
        {"rate leading the thermometer 15 s", "outside", OLeadRate},
    };
    return s;
}

}  // namespace gyrocal::bench
