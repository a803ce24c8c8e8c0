// Benchmark (not a test): ramp calibration against the plateau procedures, side by side on the
// same simulated units, judged on a held-out record none of the calibrations saw; and the chamber
// time each needed. Prints one table and the machine.
//
// In-process (tests/support/virtual_lab: the pure libraries the processes wrap, on the simulated
// clock): the real processes would take the simulated time / speed (~2.5 h / 30 = 5 min per
// plateau run) where the virtual lab takes seconds.
// Per preset (610, 613) and seed, the same units are calibrated by:
//   five        -40, -10, 25, 55, 85 degC plateaus, fitter method wls (order on evidence)
//   seed3       -10, 30, 60 degC plateaus, fitter method 3point (the seed's equations)
//   ramp R      continuous ramps start -> -40 -> 85 degC at R degC/min (--rates), +90/-90 pairs
//               every --turn-interval-s, the ramp fitter (analysis binning and term selection)
// rig thermal lags at their defaults (air 30 s, package 200 s, sensor 15 s).
// Chamber time = simulated time from the run's first order to its stop.
// Held-out: one record per seed and preset (same units, fresh noise after a lead-in longer than
// every calibration): 25 -> -40 -> 85 -> 25 degC at --held-out-rate, unit still; each set applied
// by the live compensator's library (clip). Figures over every unit: rate RMS of the 10 s bin
// means of (compensated - true rate), drift = RMS over units of the integrated error / duration;
// "truth" rows are the rig's true model on the same samples (at the die, and at the measured
// temperature: the limit any model of the measured temperature has).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "lcmtypes/text/number.hpp"
#include "tests/bench/procedure/held_out_row.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/support/virtual_lab/held_out.hpp"
#include "tests/support/virtual_lab/virtual_lab.hpp"

namespace {

using namespace gyrocal;

struct Config {
    std::string label;
    std::string profile;
    std::vector<double> setpoints_c;
    fit::Method method = fit::Method::kAuto;
    double rate_c_per_min = 3.0;
};

// A configuration's held-out figures, its chamber hours and the offset term lists its sets chose.
struct RampRow : bench::Row {
    std::vector<double> chamber_h;
    int incomplete = 0;
    std::map<std::string, int> terms;  // offset term lists chosen -> count
};

std::string TermList(const model::Model& m) {
    std::string s;
    for (const auto& t : m.term_names) s += (s.empty() ? "" : ",") + t;
    return s;
}

std::vector<Config> Configs(const std::vector<double>& rates,
                            const std::vector<double>& waypoints) {
    std::vector<Config> c = {
        {"five (plateau)", "five", {-40.0, -10.0, 25.0, 55.0, 85.0}, fit::Method::kWls},
        {"seed3 (3point)", "seed3", {-10.0, 30.0, 60.0}, fit::Method::kThreePoint},
    };
    for (double r : rates)
        c.push_back({"ramp " + text::PrintfOrDash("%.1f", r) + " C/min", "ramp", waypoints,
                     fit::Method::kAuto, r});
    return c;
}

// One calibration; false when it did not complete with a set for every unit.
bool Calibrate(const Config& k, const sim::RigConfig& rig, double turn_s, double dwell_s,
               virtual_lab::RunResult& r) {
    virtual_lab::LabConfig c = virtual_lab::LabConfig::For(k.profile, k.method);
    c.procedure.profile.setpoints_c = k.setpoints_c;
    c.procedure.ramp_rate_c_per_min = k.rate_c_per_min;
    c.procedure.turn_interval_s = turn_s;
    c.procedure.dwell_s = dwell_s;
    c.ramp_fitter.refit_interval_s = 86400.0;  // no fit during the run (no early stop here)
    c.rig = rig;
    r = virtual_lab::Run(c);
    return r.outcome == "completed" && static_cast<int>(r.final_sets.size()) == rig.num_units;
}

}  // namespace

int main(int argc, char** argv) {
    int seeds = 3, first_seed = 1, units = 4;
    std::vector<std::string> presets = {"610", "613"};
    std::vector<double> rates = {1.0, 2.0, 3.0}, waypoints = {-40.0, 85.0};
    double turn_s = 300.0, dwell_s = 300.0, held_out_rate = 0.5;
    CLI::App app{
        "gyrocal_bench_ramp: ramp vs plateau calibration on a held-out record.\n"
        "Exit codes: 0 done, 1 a run failed, 2 bad options."};
    app.add_option("--seeds", seeds, "rig seeds per preset")->check(CLI::Range(1, 100));
    app.add_option("--first-seed", first_seed, "first rig seed")->check(CLI::Range(1, 1000000));
    app.add_option("--units", units, "units per seed")->check(CLI::Range(1, 16));
    app.add_option("--presets", presets, "module presets (610, 613)")->delimiter(',');
    app.add_option("--rates", rates, "ramp rates [degC/min], each (0, 3]")->delimiter(',');
    app.add_option("--waypoints-c", waypoints, "ramp waypoints [degC]")->delimiter(',');
    app.add_option("--turn-interval-s", turn_s, "[s] between +90/-90 pairs")->capture_default_str();
    app.add_option("--dwell-s", dwell_s, "[s] at each waypoint")->capture_default_str();
    app.add_option("--held-out-rate", held_out_rate, "held-out ramp [degC/min]")
        ->check(CLI::Range(0.05, 3.0));
    try {
        app.parse(argc, argv);
        for (const auto& p : presets) sim::PresetByName(p);
    } catch (const sim::ConfigError& e) {
        std::cerr << "gyrocal_bench_ramp: " << e.what() << "\n";
        return 2;
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    const std::vector<Config> configs = Configs(rates, waypoints);
    gyrocal::bench::PrintContext(argc, argv);
    const auto wall0 = std::chrono::steady_clock::now();
    int failures = 0;
    std::printf(
        "gyrocal_bench_ramp: %d seeds (%d..) x %d units per preset; held-out 25 -> -40 -> "
        "85 -> 25 degC at %.2f degC/min, unit still, 10 s bins; ramp waypoints",
        seeds, first_seed, units, held_out_rate);
    for (double w : waypoints) std::printf(" %g", w);
    std::printf(" degC, turns every %g s, dwell %g s\n", turn_s, dwell_s);
    for (const std::string& preset : presets) {
        std::vector<RampRow> rows(configs.size() + 2);
        for (size_t k = 0; k < configs.size(); ++k) rows[k].label = configs[k].label;
        rows[configs.size()].label = "truth @ die";
        rows[configs.size() + 1].label = "truth @ T_meas";
        for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
            sim::RigConfig rig = sim::RigConfig::Defaults();
            rig.seed = static_cast<uint64_t>(seed);
            rig.num_units = units;
            rig.preset = sim::PresetByName(preset);
            std::vector<virtual_lab::Candidate> candidates;
            int64_t longest_us = 0;
            for (size_t k = 0; k < configs.size(); ++k) {
                virtual_lab::RunResult r;
                if (!Calibrate(configs[k], rig, turn_s, dwell_s, r)) {
                    std::cerr << preset << " seed " << seed << " " << configs[k].label << ": "
                              << r.outcome << " " << r.outcome_reason << "\n";
                    ++rows[k].incomplete;
                    ++failures;
                }
                longest_us = std::max(longest_us, r.end_utime - rig.start_utime);
                rows[k].chamber_h.push_back(r.chamber_hours());
                for (const auto& [id, set] : r.final_sets) ++rows[k].terms[TermList(set.offset)];
                candidates.push_back(r.final_sets);
            }
            virtual_lab::HeldOutProfile profile;
            profile.ramp_c_per_min = held_out_rate;
            profile.lead_in_s = 1e-6 * static_cast<double>(longest_us) + 600.0;
            const auto h = virtual_lab::EvaluateHeldOut(rig, profile, candidates);
            for (const auto& s : h.sensors) {
                for (size_t k = 0; k < configs.size(); ++k)
                    if (candidates[k].count(s.sensor_id))
                        rows[k].Add(s.err_dps[k], s.angle_deg[k], h.duration_s);
                rows[configs.size()].Add(s.floor_dps, s.floor_angle_deg, h.duration_s);
                rows[configs.size() + 1].Add(s.floor_meas_dps, s.floor_meas_angle_deg,
                                             h.duration_s);
            }
        }
        const double five_h = rows[0].chamber_h.empty() ? NAN : [&] {
            double sum = 0;
            for (double v : rows[0].chamber_h) sum += v;
            return sum / rows[0].chamber_h.size();
        }();
        std::printf("\npreset %s\n%-18s %16s %9s %12s %10s %8s\n", preset.c_str(), "procedure",
                    "chamber h", "vs five", "rate RMS", "drift", "RMS/");
        std::printf("%-18s %16s %9s %12s %10s %8s\n", "", "mean [min-max]", "", "[deg/s]",
                    "[deg/h]", "truth");
        const double limit = rows[configs.size() + 1].Rms();
        for (const RampRow& r : rows) {
            std::string hours = "-", ratio = "-";
            if (!r.chamber_h.empty()) {
                double sum = 0;
                for (double v : r.chamber_h) sum += v;
                const double mean = sum / r.chamber_h.size();
                hours = text::PrintfOrDash("%.2f", mean) + " [" +
                        text::PrintfOrDash(
                            "%.2f", *std::min_element(r.chamber_h.begin(), r.chamber_h.end())) +
                        "-" +
                        text::PrintfOrDash(
                            "%.2f", *std::max_element(r.chamber_h.begin(), r.chamber_h.end())) +
                        "]";
                ratio = text::PrintfOrDash("%.2f", mean / five_h);
            }
            std::printf("%-18s %16s %9s %12s %10s %8s\n", r.label.c_str(), hours.c_str(),
                        ratio.c_str(), text::PrintfOrDash("%.4f", r.Rms()).c_str(),
                        text::PrintfOrDash("%.2f", r.Drift()).c_str(),
                        text::PrintfOrDash("%.2f", r.Rms() / limit).c_str());
        }
        for (size_t k = 0; k < configs.size(); ++k) {
            std::printf("  %s offset terms:", configs[k].label.c_str());
            for (const auto& [t, n] : rows[k].terms) std::printf(" {%s} x%d", t.c_str(), n);
            std::printf("\n");
        }
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    std::printf("wall time %.1f s\n", wall_s);
    return failures == 0 ? 0 : 1;
}
