#include "tests/bench/analysis/verdict_effects.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "processors/model/terms.hpp"

namespace gyrocal::bench {

namespace {

struct Grid {  // 1 s means of the measured temperature and what follows from them
    std::vector<double> temp, rate, lead_rate, abs_rate, accel, branch, wander;
};

double At(const std::vector<double>& v, long k) {
    return v[static_cast<size_t>(std::clamp<long>(k, 0, static_cast<long>(v.size()) - 1))];
}

Grid MakeGrid(const PostHoc& p, const analysis::SensorRun& run) {
    Grid g;
    const int64_t t0 = run.samples.front().utime;
    const auto n = static_cast<size_t>((run.samples.back().utime - t0) / 1'000'000 + 1);
    std::vector<double> sum(n, 0.0), cnt(n, 0.0);
    for (const analysis::GyroSample& s : run.samples) {
        const auto k = static_cast<size_t>((s.utime - t0) / 1'000'000);
        sum[k] += s.temp_c, cnt[k] += 1;
    }
    g.temp.resize(n);
    for (size_t k = 0; k < n; ++k)
        g.temp[k] = cnt[k] > 0 ? sum[k] / cnt[k] : (k ? g.temp[k - 1] : 25);
    g.rate.resize(n), g.lead_rate.resize(n), g.abs_rate.resize(n), g.accel.resize(n),
        g.branch.resize(n), g.wander.resize(n);
    double memory = g.temp[0];
    const double half = 0.5 * p.branch_width_c;
    std::mt19937_64 rng(p.wander_seed);
    std::normal_distribution<double> normal;
    const double phi = std::exp(-1.0 / p.wander_tau_s);
    double w = p.wander_v * normal(rng);
    for (size_t k = 0; k < n; ++k) {
        const long i = static_cast<long>(k);
        g.rate[k] = (g.temp[k] - At(g.temp, i - 30)) / 30.0;
        g.lead_rate[k] = (At(g.temp, i + 15) - At(g.temp, i - 15)) / 30.0;
        g.abs_rate[k] = std::fabs(At(g.temp, i + 60) - At(g.temp, i - 60)) / 120.0;
        g.accel[k] = (At(g.temp, i + 90) - 2 * g.temp[k] + At(g.temp, i - 90)) / (90.0 * 90.0);
        memory = std::clamp(memory, g.temp[k] - half, g.temp[k] + half);
        g.branch[k] = (g.temp[k] - memory) / half;
        w = phi * w + p.wander_v * std::sqrt(1 - phi * phi) * normal(rng);
        g.wander[k] = w;
    }
    return g;
}

double Listed(const PostHoc& p, const Grid& g, size_t k, const analysis::GyroSample& s, double t) {
    const double dT = s.temp_c - 25.0;
    double v = p.rate_v_per_c_per_s * g.rate[k] + p.branch_v * g.branch[k] +
               p.cubic_v_per_c3 * dT * dT * dT + p.warmup_v * std::exp(-t / p.warmup_tau_s);
    if (p.supply_v_per_v != 0 && std::isfinite(s.supply_v))
        v += p.supply_v_per_v * (s.supply_v - model::kNominalSupplyV);
    return v;
}

double Outside(const PostHoc& p, const Grid& g, size_t k, const analysis::GyroSample& s, double t) {
    const double dT = s.temp_c - 25.0;
    double v = p.lead_rate_v_per_c_per_s * g.lead_rate[k] +
               p.abs_rate_v_per_c_per_s * g.abs_rate[k] + p.accel_v_per_c_per_s2 * g.accel[k] +
               p.quartic_v_per_c4 * dT * dT * dT * dT + p.drift_v_per_h * t / 3600.0 +
               p.wander_v * (p.wander_v != 0 ? g.wander[k] / p.wander_v : 0.0) +
               p.warmup2_v * std::exp(-t / p.warmup2_tau_s);
    if (p.hot_bend_v != 0) v += p.hot_bend_v * std::exp((s.temp_c - 70.0) / p.hot_bend_c);
    if (p.saw_v != 0) v += p.saw_v * (t / p.saw_s - std::floor(t / p.saw_s) - 0.5);
    for (const auto& [at, dv] : p.steps)
        if (t >= at) v += dv;
    return v;
}

}  // namespace

PostHocValues Evaluate(const PostHoc& p, const analysis::SensorRun& run) {
    PostHocValues out;
    if (run.samples.empty()) return out;
    const Grid g = MakeGrid(p, run);
    const int64_t t0 = run.samples.front().utime;
    out.listed_v.reserve(run.samples.size());
    out.outside_v.reserve(run.samples.size());
    for (const analysis::GyroSample& s : run.samples) {
        const auto k = static_cast<size_t>((s.utime - t0) / 1'000'000);
        const double t = (s.utime - t0) * 1e-6;
        out.listed_v.push_back(Listed(p, g, k, s, t));
        out.outside_v.push_back(Outside(p, g, k, s, t));
    }
    return out;
}

void AddTo(analysis::SensorRun& run, const std::vector<double>& v) {
    for (size_t i = 0; i < run.samples.size() && i < v.size(); ++i) run.samples[i].gyro_v += v[i];
}

}  // namespace gyrocal::bench
