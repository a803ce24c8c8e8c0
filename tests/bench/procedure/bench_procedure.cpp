// Benchmark (not a test): the seed's 3-point method versus the N-point fit, on the same simulated
// units, judged on a held-out temperature profile none of the calibrations saw; and the chamber
// time each calibration needed. Prints one table and the machine.
//
// Per seed, the same units (RigConfig seed) are calibrated three times by the in-process
// pipeline (tests/support/virtual_lab: rig -> plateau detector -> rotation estimator -> fitter,
// driven by the sequencer's Procedure):
//   seed3        -10, 30, 60 degC           method 3point (the seed's equations, offset and S)
//   five-narrow  -10, 7.5, 25, 42.5, 60     method wls    (same range as seed3: like with like,
//                                                          only the number of points differs)
//   five         -40, -10, 25, 55, 85       method wls    (the default profile: the wide range)
// Chamber time = simulated time from the run's first order to its last sensitivity point.
// Then ONE held-out record per seed (same units, fresh noise: it starts after a lead-in longer
// than any of the calibrations, see held_out.hpp): the chamber ramps 25 -> -40 -> 85 -> 25 degC
// at --ramp-c-per-min, unit still, and every coefficient set is applied to it by the live
// compensator's library (range policy clip, its default). Errors are 10 s bin means (see
// held_out.hpp for why); "floor" rows are the perfect model on the same samples.
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
#include "tests/bench/support/bench_context.hpp"
#include "tests/support/virtual_lab/held_out.hpp"
#include "tests/support/virtual_lab/virtual_lab.hpp"

namespace {

using namespace gyrocal;
using virtual_lab::Score;

struct Config {
    std::string label;
    std::vector<double> setpoints_c;
    fit::Method method;
};

// Pooled figures of one row over every unit of every seed.
struct Row {
    std::string label, method, points;
    std::vector<double> chamber_h;
    double sum2_all = 0, sum2_common = 0;
    long n_all = 0, n_common = 0;
    double sum2_model_all = 0, sum2_model_common = 0;  // err - floor_meas: the model alone
    long plateaus = 0, rotations = 0, sets = 0;
    std::map<int, int> offset_degrees;  // terms - 1 -> count
    double sum_chi2 = 0;                // offset fits: chi2 and dof with the plateaus' SEMs
    long sum_dof = 0;
    double max_in = 0, max_out = 0;
    bool bins_out_any = false;
    double sum2_drift = 0, worst_hour = 0;
    int units = 0, incomplete = 0;

    void Add(const std::vector<double>& err, const std::vector<double>& temp, double range_min,
             double range_max, double angle_deg, double duration_s, double bin_s,
             const std::vector<double>& floor_meas, double common_min, double common_max) {
        const Score s =
            virtual_lab::ScoreBins(err, temp, range_min, range_max, angle_deg, duration_s);
        max_in = std::max(max_in, s.max_in_dps);
        max_out = std::max(max_out, s.max_out_dps);
        bins_out_any = bins_out_any || s.bins_out > 0;
        sum2_drift += s.drift_dph * s.drift_dph;
        ++units;
        for (size_t i = 0; i < err.size(); ++i) {
            if (!std::isfinite(err[i])) continue;
            const double m = err[i] - floor_meas[i];
            sum2_all += err[i] * err[i];
            sum2_model_all += m * m;
            ++n_all;
            if (temp[i] >= common_min && temp[i] <= common_max) {
                sum2_common += err[i] * err[i];
                sum2_model_common += m * m;
                ++n_common;
            }
        }
        // Worst hour: the largest |mean error| over any 1 h stretch of bins, as deg/h.
        const size_t w = static_cast<size_t>(std::lround(3600.0 / bin_s));
        double sum = 0;
        for (size_t i = 0; i < err.size(); ++i) {
            sum += std::isfinite(err[i]) ? err[i] : 0.0;
            if (i >= w) sum -= std::isfinite(err[i - w]) ? err[i - w] : 0.0;
            if (i + 1 >= w) worst_hour = std::max(worst_hour, std::abs(sum / w) * 3600.0);
        }
    }
};

}  // namespace

int main(int argc, char** argv) {
    int seeds = 6, first_seed = 1, units = 4;
    double ramp_c_per_min = 0.5, bin_s = 10.0;
    std::vector<std::string> effects;
    CLI::App app{
        "gyrocal_bench_procedure: seed 3-point vs N-point fit on a held-out temperature profile.\n"
        "Exit codes: 0 done, 1 a run failed, 2 bad options."};
    app.add_option("--seeds", seeds, "number of rig seeds (each: new units)")
        ->check(CLI::Range(1, 100));
    app.add_option("--first-seed", first_seed, "first rig seed")->check(CLI::Range(1, 1000000));
    app.add_option("--units", units, "units per seed")->check(CLI::Range(1, 16));
    app.add_option("--ramp-c-per-min", ramp_c_per_min, "held-out ramp rate [degC/min]")
        ->check(CLI::Range(0.05, 3.0));
    app.add_option("--bin-s", bin_s, "held-out error bin [s]")->check(CLI::Range(0.1, 600.0));
    app.add_option("--effect", effects,
                   "undeclared rig effect NAME=VALUE (repeatable; sim/config.hpp), default none");
    sim::EffectsConfig effects_config;
    try {
        app.parse(argc, argv);
        for (const std::string& e : effects) sim::ParseEffect(effects_config, e);
    } catch (const sim::ConfigError& e) {
        std::cerr << "gyrocal_bench_procedure: " << e.what() << "\n";
        return 2;
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }

    const std::vector<Config> configs = {
        {"seed3", {-10.0, 30.0, 60.0}, fit::Method::kThreePoint},
        {"five-narrow", {-10.0, 7.5, 25.0, 42.5, 60.0}, fit::Method::kWls},
        {"five", {-40.0, -10.0, 25.0, 55.0, 85.0}, fit::Method::kWls},
    };
    const size_t nc = configs.size();
    // Rows: each configuration under the compensator's default policy (clip), the two narrow ones
    // again with the polynomial extrapolated outside their range, then the two floors.
    const std::vector<size_t> extrapolated = {0, 1};
    std::vector<Row> rows(nc + extrapolated.size() + 2);
    for (size_t k = 0; k < nc; ++k) {
        rows[k].label = configs[k].label;
        rows[k].method = fit::ToString(configs[k].method);
    }
    for (size_t j = 0; j < extrapolated.size(); ++j) {
        rows[nc + j].label = configs[extrapolated[j]].label + " (extrap)";
        rows[nc + j].method = rows[extrapolated[j]].method;
    }
    Row& floor_die = rows[rows.size() - 2];
    Row& floor_meas = rows[rows.size() - 1];
    floor_die.label = "floor: truth@die";
    floor_meas.label = "floor: truth@T_meas";

    gyrocal::bench::PrintContext(argc, argv);
    const auto wall0 = std::chrono::steady_clock::now();
    virtual_lab::HeldOutProfile profile;
    profile.waypoints_c = {-40.0, 85.0, 25.0};
    profile.ramp_c_per_min = ramp_c_per_min;
    profile.hold_s = 600.0;
    profile.bin_s = bin_s;
    compensator::CompensatorOptions extrapolate = compensator::CompensatorOptions::Defaults();
    extrapolate.range_policy = model::RangePolicy::kExtrapolate;
    double held_out_h = 0;
    int failures = 0;
    for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
        std::vector<virtual_lab::Candidate> candidates;
        int64_t longest_us = 0;
        sim::RigConfig rig;
        for (size_t k = 0; k < nc; ++k) {
            virtual_lab::LabConfig c = virtual_lab::LabConfig::For("five", configs[k].method);
            c.procedure.profile = {configs[k].label, configs[k].setpoints_c};
            c.rig.seed = static_cast<uint64_t>(seed);
            c.rig.num_units = units;
            c.rig.effects = effects_config;
            rig = c.rig;
            const virtual_lab::RunResult r = virtual_lab::Run(c);
            longest_us = std::max(longest_us, r.end_utime - c.rig.start_utime);
            if (r.outcome != "completed" || static_cast<int>(r.final_sets.size()) != units) {
                std::cerr << "seed " << seed << " " << configs[k].label << ": " << r.outcome << " "
                          << r.outcome_reason << ", " << r.final_sets.size() << " sets\n";
                ++rows[k].incomplete;
                ++failures;
            }
            rows[k].chamber_h.push_back(r.chamber_hours());
            rows[k].plateaus += static_cast<long>(r.plateaus.size());
            for (const auto& p : r.sensitivity_points) rows[k].rotations += p.accepted ? 1 : 0;
            for (const auto& [id, set] : r.final_sets) {
                ++rows[k].sets;
                ++rows[k].offset_degrees[static_cast<int>(set.offset.term_names.size()) - 1];
                const model::Evaluator off(set.offset);
                int n = 0;
                for (const auto& p : r.plateaus) {
                    if (p.sensor_id != id) continue;
                    model::ModelInputs in;
                    in.temp_c = p.temp_mean_c;
                    const double z =
                        (p.gyro_mean_v - off.Value(in, model::RangePolicy::kClip)) / p.gyro_sem_v;
                    rows[k].sum_chi2 += z * z;
                    ++n;
                }
                rows[k].sum_dof += n - static_cast<long>(set.offset.term_names.size());
            }
            candidates.push_back(r.final_sets);
        }
        // Fresh noise: the record starts after the longest calibration of this seed ended.
        profile.lead_in_s = 1e-6 * static_cast<double>(longest_us) + 600.0;
        const virtual_lab::HeldOutResult h = virtual_lab::EvaluateHeldOut(rig, profile, candidates);
        std::vector<virtual_lab::Candidate> narrow;
        for (size_t k : extrapolated) narrow.push_back(candidates[k]);
        const virtual_lab::HeldOutResult hx =
            virtual_lab::EvaluateHeldOut(rig, profile, narrow, extrapolate);
        held_out_h = h.duration_s / 3600.0;
        for (size_t u = 0; u < h.sensors.size(); ++u) {
            const virtual_lab::SensorHeldOut& s = h.sensors[u];
            // The range every calibration of this unit covers (measured temperature): where all
            // are compared like with like, none clipped or extrapolated.
            double common_min = -1e9, common_max = 1e9;
            for (const auto& cand : candidates) {
                const auto it = cand.find(s.sensor_id);
                if (it == cand.end()) continue;
                common_min = std::max(common_min, it->second.offset.temp_min_c);
                common_max = std::min(common_max, it->second.offset.temp_max_c);
            }
            auto add = [&](Row& row, const virtual_lab::SensorHeldOut& rec, size_t index,
                           const virtual_lab::Candidate& cand) {
                const auto it = cand.find(rec.sensor_id);
                if (it == cand.end()) return;
                row.Add(rec.err_dps[index], rec.temp_c, it->second.offset.temp_min_c,
                        it->second.offset.temp_max_c, rec.angle_deg[index], h.duration_s, h.bin_s,
                        rec.floor_meas_dps, common_min, common_max);
            };
            for (size_t k = 0; k < nc; ++k) add(rows[k], s, k, candidates[k]);
            for (size_t j = 0; j < extrapolated.size(); ++j)
                add(rows[nc + j], hx.sensors[u], j, narrow[j]);
            floor_die.Add(s.floor_dps, s.temp_c, -1e9, 1e9, s.floor_angle_deg, h.duration_s,
                          h.bin_s, s.floor_meas_dps, common_min, common_max);
            floor_meas.Add(s.floor_meas_dps, s.temp_c, -1e9, 1e9, s.floor_meas_angle_deg,
                           h.duration_s, h.bin_s, s.floor_meas_dps, common_min, common_max);
        }
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

    const double floor_rms = std::sqrt(floor_die.sum2_all / std::max(1L, floor_die.n_all));
    std::printf(
        "gyrocal_bench_procedure: %d seeds (%d..%d) x %d units = %d units per row; held-out:"
        " 25 -> -40 -> 85 -> 25 degC at %.2f degC/min (%.1f h), unit still, %g s bins\n",
        seeds, first_seed, first_seed + seeds - 1, units, floor_die.units, ramp_c_per_min,
        held_out_h, bin_s);
    std::string effect_list;
    for (const std::string& e : effects) effect_list += " " + e;
    std::printf("rig effects:%s\n", effect_list.empty() ? " none" : effect_list.c_str());
    const char* hdr = "%-20s %-6s %-9s %-15s %8s %8s %8s %8s %8s %8s %8s %8s %6s\n";
    std::printf(hdr, "profile", "method", "pl+rot", "chamber h", "RMS all", "RMS", "model", "model",
                "max|e|", "max|e|", "drift", "worst", "RMS/");
    std::printf(hdr, "", "", "/unit", "mean [min-max]", "", "common", "err all", "common", "in cal",
                "out cal", "rms", "1 h", "floor");
    std::printf(hdr, "", "", "", "[h]", "[deg/s]", "[deg/s]", "[deg/s]", "[deg/s]", "[deg/s]",
                "[deg/s]", "[deg/h]", "[deg/h]", "");
    for (const Row& r : rows) {
        std::string hours = "-", points = "-";
        if (!r.chamber_h.empty()) {
            double sum = 0;
            for (double v : r.chamber_h) sum += v;
            hours = text::PrintfOrDash("%.2f", sum / r.chamber_h.size()) + " [" +
                    text::PrintfOrDash("%.2f",
                                       *std::min_element(r.chamber_h.begin(), r.chamber_h.end())) +
                    "-" +
                    text::PrintfOrDash("%.2f",
                                       *std::max_element(r.chamber_h.begin(), r.chamber_h.end())) +
                    "]";
            const double per = static_cast<double>(seeds) * units;
            points = text::PrintfOrDash("%.3g", r.plateaus / per) + "+" +
                     text::PrintfOrDash("%.3g", r.rotations / per);
        }
        auto rms = [](double sum2, long n) { return n > 0 ? std::sqrt(sum2 / n) : NAN; };
        std::printf(
            hdr, r.label.c_str(), r.method.c_str(), points.c_str(), hours.c_str(),
            text::PrintfOrDash("%.4f", rms(r.sum2_all, r.n_all)).c_str(),
            text::PrintfOrDash("%.4f", rms(r.sum2_common, r.n_common)).c_str(),
            text::PrintfOrDash("%.4f", rms(r.sum2_model_all, r.n_all)).c_str(),
            text::PrintfOrDash("%.4f", rms(r.sum2_model_common, r.n_common)).c_str(),
            text::PrintfOrDash("%.4f", r.max_in).c_str(),
            r.bins_out_any ? text::PrintfOrDash("%.4f", r.max_out).c_str() : "-",
            text::PrintfOrDash("%.1f", std::sqrt(r.sum2_drift / std::max(1, r.units))).c_str(),
            text::PrintfOrDash("%.1f", r.worst_hour).c_str(),
            text::PrintfOrDash("%.2f", rms(r.sum2_all, r.n_all) / floor_rms).c_str());
    }
    for (size_t k = 0; k < nc; ++k) {
        std::printf("%s: offset degree chosen:", configs[k].label.c_str());
        for (const auto& [d, n] : rows[k].offset_degrees) std::printf(" d%d x%d", d, n);
        if (rows[k].sum_dof > 0)
            std::printf("; offset chi2/dof with the plateau SEMs %.2f (dof %ld)",
                        rows[k].sum_chi2 / rows[k].sum_dof, rows[k].sum_dof);
        std::printf("; incomplete runs %d\n", rows[k].incomplete);
    }
    std::printf("wall time %.1f s\n", wall_s);
    return failures == 0 ? 0 : 1;
}
