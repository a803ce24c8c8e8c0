// Benchmark (not a test): on the same held-out stretch of simulated runs, the seed's 3-point
// method, the N-point fit, and the analysis' extended model, versus the noise floor.
//
// Each run (one unit; setpoints -10, 50, 10, 70, 30, 60, 20 with ramps between; see sim_run.hpp)
// is split by the analysis into training data and held-out bins (interleaved blocks: analyze.hpp,
// step 2). Every method is fitted on the training part only (the plateaus and rotations outside
// the held-out blocks) and applied to every 10 s still bin held out:
//   3-point : the seed's equations on 3 training plateaus (coldest, nearest mid-range, hottest, in
//             acquisition order) for the offset, and on the rotations of those 3 setpoints for
//             the sensitivity;
//   N-point : weighted least squares with order selection on all training plateaus / rotations
//             (what the fitter publishes);
//   extended: the analysis' model (declared terms + the effects it added), fitted on the training
//             bins; the N-point sensitivity.
// Figures: rate RMS [deg/s] = RMS of (gyro_v - offset(T)) / S(T); drift [deg/h] = RMS over the
// held-out blocks of |integrated angle| / block duration; floor = the Allan deviation of the
// residual at the bin length (bins.hpp) and its white-noise drift bound. Mean over seeds.
// Options: [seeds] (default 6).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/sensitivity.hpp"
#include "processors/fit/fit.hpp"
#include "processors/fit/levels.hpp"
#include "processors/model/inputs.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/processors/analysis/sim_run.hpp"

using namespace gyrocal;

namespace {

struct Figures {
    double rate_rms_dps = NAN, drift_dph = NAN;
};

Figures OnHeldOut(const analysis::BinnedRun& binned, const std::vector<int>& held,
                  const model::Model& offset, const model::Model& sens, double period_s) {
    const Eigen::VectorXd vo = binned.Values(offset);
    const model::Evaluator es(sens);
    const gyrocal_tracker_config_t sc = model::TrackerConfigFor(sens);
    // Held-out blocks are runs of consecutive held bins; drift per block, RMS over blocks.
    double ss = 0, angle = 0, dur = 0, ss_drift = 0;
    int blocks = 0;
    for (size_t k = 0; k < held.size(); ++k) {
        const auto i = static_cast<size_t>(held[k]);
        const analysis::Bin& b = binned.bins()[i];
        const double rate = (b.gyro_v - vo[static_cast<Eigen::Index>(i)]) /
                            es.Value(binned.Inputs(i, sc), model::RangePolicy::kClip);
        ss += rate * rate;
        angle += rate * b.n * period_s;
        dur += b.n * period_s;
        const bool block_ends =
            k + 1 == held.size() ||
            binned.bins()[static_cast<size_t>(held[k + 1])].start_utime - b.end_utime > 60'000'000;
        if (block_ends) {
            ss_drift += std::pow(angle / dur * 3600.0, 2);
            ++blocks;
            angle = dur = 0;
        }
    }
    return {std::sqrt(ss / held.size()), std::sqrt(ss_drift / blocks)};
}

// Plateau / rotation points outside the held-out bins' time.
bool InHeldTime(const analysis::BinnedRun& binned, const std::vector<int>& held, int64_t start,
                int64_t end) {
    for (int i : held) {
        const analysis::Bin& b = binned.bins()[static_cast<size_t>(i)];
        if (start < b.end_utime + 60'000'000 && end > b.start_utime - 60'000'000) return true;
    }
    return false;
}

std::vector<fit::FitPoint> OffsetPoints(const analysis::SensorRun& run,
                                        const analysis::BinnedRun& binned,
                                        const std::vector<int>& held) {
    std::vector<fit::FitPoint> pts;
    for (const auto& p : run.plateaus) {
        if (InHeldTime(binned, held, p.start_utime, p.end_utime)) continue;
        fit::FitPoint f;
        f.inputs.temp_c = p.temp_mean_c;
        f.y = p.gyro_mean_v;
        f.sigma_y = p.gyro_sem_v;
        f.id = p.plateau_id;
        pts.push_back(f);
    }
    return pts;
}
std::vector<fit::FitPoint> SensPoints(const analysis::SensorRun& run,
                                      const analysis::BinnedRun& binned,
                                      const std::vector<int>& held) {
    std::vector<fit::FitPoint> pts;
    for (const auto& s : run.sensitivities) {
        if (!InHeldTime(binned, held, s.utime - 10'000'000, s.utime))
            pts.push_back(analysis::SensitivityFitPoint(s));
    }
    return pts;
}

// The seed's 3 points: coldest, nearest mid-range, hottest plateau, in acquisition order; and the
// rotations whose temperature is within 3 degC of those plateaus.
void SeedPoints(const std::vector<fit::FitPoint>& off, const std::vector<fit::FitPoint>& sens,
                std::vector<fit::FitPoint>* off3, std::vector<fit::FitPoint>* sens3) {
    size_t lo = 0, hi = 0;
    for (size_t i = 0; i < off.size(); ++i) {
        if (off[i].inputs.temp_c < off[lo].inputs.temp_c) lo = i;
        if (off[i].inputs.temp_c > off[hi].inputs.temp_c) hi = i;
    }
    const double mid = 0.5 * (off[lo].inputs.temp_c + off[hi].inputs.temp_c);
    size_t md = lo == 0 && hi != 0 ? 0 : 0;
    double best = INFINITY;
    for (size_t i = 0; i < off.size(); ++i)
        if (i != lo && i != hi && std::fabs(off[i].inputs.temp_c - mid) < best)
            best = std::fabs(off[i].inputs.temp_c - mid), md = i;
    std::vector<size_t> idx = {lo, md, hi};
    std::sort(idx.begin(), idx.end());
    for (size_t i : idx) off3->push_back(off[i]);
    for (const auto& s : sens)
        for (size_t i : idx)
            if (std::fabs(s.inputs.temp_c - off[i].inputs.temp_c) < 3.0) sens3->push_back(s);
}

}  // namespace

int main(int argc, char** argv) {
    const int seeds = bench::IntArg(argc, argv, 1, 6);
    if (seeds < 1 || seeds > 1000) return bench::Usage(argv, "[seeds 1..1000]");
    bench::PrintContext(argc, argv);
    std::printf(
        "gyrocal analysis benchmark: held-out stretch of simulated runs, mean over %d seeds\n",
        seeds);
    struct Config {
        const char* label;
        std::vector<std::pair<const char*, double>> effects;
    };
    const std::vector<Config> configs = {{"clean", {}},
                                         {"temp_rate=1e-4", {{"temp_rate", 1e-4}}},
                                         {"hysteresis=1e-3", {{"hysteresis", 1e-3}}},
                                         {"temp_cubic=2e-8", {{"temp_cubic", 2e-8}}},
                                         {"supply=0.05", {{"supply", 0.05}}},
                                         {"warmup=2e-3", {{"warmup", 2e-3}}},
                                         {"rate+supply", {{"temp_rate", 1e-4}, {"supply", 0.05}}}};
    std::printf("\n%-16s %-9s %13s %11s %9s   %s\n", "effect in rig", "method", "rate_rms_dps",
                "drift_dph", "x floor", "found by the analysis");
    const auto t_start = std::chrono::steady_clock::now();
    for (const Config& c : configs) {
        double rms[3] = {0, 0, 0}, drift[3] = {0, 0, 0}, floor_rms = 0, floor_drift = 0;
        int used = 0, found = 0;
        for (int s = 1; s <= seeds; ++s) {
            analysis::testing::SimRunOptions o;
            o.seed = 500 + s;
            o.setpoints_c = {-10.0, 50.0, 10.0, 70.0, 30.0, 60.0, 20.0};
            for (const auto& [name, value] : c.effects) sim::SetEffect(o.effects, name, value);
            const auto sr = analysis::testing::MakeSimRun(o);
            const analysis::SensorResult r = analysis::Analyze(sr.run);
            if (!r.holdout_after_offset || !std::isfinite(r.floor_rate_rms_dps)) continue;
            bool all = true;
            for (const auto& [name, value] : c.effects) {
                bool hit = false;
                for (const auto& a : r.added) hit = hit || a.effect == name;
                all = all && hit;
            }
            if (all && (!c.effects.empty() || r.added.empty())) ++found;
            const analysis::BinnedRun binned(sr.run, analysis::BinOptions::Defaults());
            const double period_s = analysis::SamplePeriodS(sr.run);
            const auto off = OffsetPoints(sr.run, binned, r.holdout_bins);
            const auto sens = SensPoints(sr.run, binned, r.holdout_bins);
            std::vector<fit::FitPoint> off3, sens3;
            SeedPoints(off, sens, &off3, &sens3);
            fit::FitOptions three;
            three.method = fit::Method::kThreePoint;
            const fit::FitResult o3 = fit::FitPolynomial(off3, model::kOffsetQuantity, three);
            const fit::FitResult s3 = fit::FitPolynomial(sens3, model::kSensitivityQuantity, three);
            const fit::FitResult on = fit::FitPolynomial(off, model::kOffsetQuantity);
            const fit::FitResult sn = fit::FitPolynomial(sens, model::kSensitivityQuantity);
            if (s == 1 && &c == &configs[0])
                std::printf(
                    "(seed %llu: %zu training plateaus, %zu training rotations, %d held-out "
                    "bins)\n",
                    static_cast<unsigned long long>(o.seed), off.size(), sens.size(),
                    r.n_holdout_bins);
            if (!o3.ok() || !s3.ok() || !on.ok() || !sn.ok()) {
                std::fprintf(stderr, "seed %d: a fit was refused: %s %s %s %s\n", s,
                             o3.detail.c_str(), s3.detail.c_str(), on.detail.c_str(),
                             sn.detail.c_str());
                continue;
            }
            const Figures f[3] = {
                OnHeldOut(binned, r.holdout_bins, o3.model, s3.model, period_s),
                OnHeldOut(binned, r.holdout_bins, on.model, sn.model, period_s),
                OnHeldOut(binned, r.holdout_bins, *r.holdout_after_offset, sn.model, period_s)};
            for (int m = 0; m < 3; ++m) {
                rms[m] += f[m].rate_rms_dps;
                drift[m] += f[m].drift_dph;
            }
            floor_rms += r.floor_rate_rms_dps;
            floor_drift += r.floor_drift_dph;
            ++used;
        }
        if (used == 0) continue;
        const char* names[3] = {"3-point", "N-point", "extended"};
        const double fl = floor_rms / used;
        char found_text[64];
        std::snprintf(found_text, sizeof found_text, "%d/%d runs", found, used);
        for (int m = 0; m < 3; ++m)
            std::printf("%-16s %-9s %13.4f %11.1f %9.2f   %s\n", m == 0 ? c.label : "", names[m],
                        rms[m] / used, drift[m] / used, rms[m] / used / fl,
                        m == 2 ? found_text : "");
        std::printf("%-16s %-9s %13.4f %11.1f %9.2f\n", "", "floor", fl, floor_drift / used, 1.0);
    }
    std::printf(
        "\nwall time %.1f s; drift floor is the white-noise bound (slow bias noise not in it)\n",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
    return 0;
}
