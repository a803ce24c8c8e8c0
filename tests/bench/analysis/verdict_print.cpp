// gyrocal_bench_verdict's tables (verdict_run.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "tests/bench/analysis/verdict_run.hpp"

namespace gyrocal::bench {

namespace {

const std::vector<std::string> kCategories = {
    "named right alone", "named right + flagged", "ambiguous", "unexplained", "wrong candidate",
    "adequate-when-not", "explained-when-not",    "adequate",  "not testable"};
const std::vector<std::string> kGroups = {"clean",     "listed", "outside",    "static shape",
                                          "transient", "shift",  "combination"};

void Confusion(const std::vector<RunFigures>& runs) {
    std::printf("| group | runs |");
    for (const std::string& c : kCategories) std::printf(" %s |", c.c_str());
    std::printf("\n|---|---|");
    for (size_t i = 0; i < kCategories.size(); ++i) std::printf("---|");
    std::printf("\n");
    std::map<std::string, int> total;
    for (const std::string& g : kGroups) {
        std::map<std::string, int> n;
        int runs_in = 0;
        for (const RunFigures& f : runs)
            if (f.group == g) ++n[f.category], ++total[f.category], ++runs_in;
        if (runs_in == 0) continue;
        std::printf("| %s | %d |", g.c_str(), runs_in);
        for (const std::string& c : kCategories) std::printf(" %d |", n[c]);
        std::printf("\n");
    }
    std::printf("| all | %zu |", runs.size());
    for (const std::string& c : kCategories) std::printf(" %d |", total[c]);
    std::printf("\n");
}

double Median(std::vector<double> v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }),
            v.end());
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

void PerScenario(const std::vector<RunFigures>& runs) {
    std::printf(
        "\n| scenario | runs | outcomes | size/floor (median) | held-out / true (median, max) "
        "|\n|---|---|---|---|---|\n");
    std::vector<std::string> order;
    for (const RunFigures& f : runs)
        if (std::find(order.begin(), order.end(), f.scenario) == order.end())
            order.push_back(f.scenario);
    for (const std::string& s : order) {
        std::map<std::string, int> n;
        std::vector<double> size, ratio;
        for (const RunFigures& f : runs) {
            if (f.scenario != s) continue;
            ++n[f.category];
            double biggest = f.outside_ratio;
            for (const EffectSize& e : f.listed) biggest = std::max(biggest, e.ratio);
            size.push_back(biggest);
            ratio.push_back(f.heldout_ratio);
        }
        std::string cats;
        int count = 0;
        for (const auto& [c, k] : n)
            cats += (cats.empty() ? "" : ", ") + c + " " + std::to_string(k), count += k;
        std::printf("| %s | %d | %s | %.1f | %.2f, %.2f |\n", s.c_str(), count, cats.c_str(),
                    Median(size), Median(ratio), *std::max_element(ratio.begin(), ratio.end()));
    }
}

void Named(const std::vector<RunFigures>& runs) {
    std::map<std::string, std::pair<int, int>> per;  // effect -> (named, above 5x)
    int named = 0, big = 0, masked_named = 0, masked_big = 0;
    for (const RunFigures& f : runs)
        for (const EffectSize& e : f.listed) {
            if (e.ratio <= 5.0) continue;
            ++big, ++per[e.effect].second;
            const bool masked = f.group == "combination";
            masked_big += masked;
            if (!e.named) continue;
            ++named, ++per[e.effect].first;
            masked_named += masked;
        }
    std::printf(
        "\nlisted effects above 5x the floor named (alone or with a flag): %d of %d (%.1f %%); "
        "in combinations %d of %d\n",
        named, big, big ? 100.0 * named / big : NAN, masked_named, masked_big);
    for (const auto& [e, p] : per) std::printf("  %-12s %d of %d\n", e.c_str(), p.first, p.second);
}

void Transfer(const std::vector<RunFigures>& runs) {
    int within = 0, n = 0, misses = 0, flagged = 0;
    for (const RunFigures& f : runs) {
        const bool listed_only = !f.listed.empty() && f.outside_ratio == 0.0;
        if (!listed_only || !std::isfinite(f.heldout_ratio)) continue;
        ++n;
        if (f.heldout_ratio <= 1.2) {
            ++within;
        } else {
            ++misses;
            flagged += f.flagged;
        }
    }
    std::printf(
        "held-out run, runs with listed effects only: extended model within 1.2x of the "
        "true model in %d of %d (%.1f %%); of the %d beyond, %d flagged by the outcome\n",
        within, n, n ? 100.0 * within / n : NAN, misses, flagged);
}

void Warmup(const std::vector<RunFigures>& runs) {
    int n = 0, named = 0, amp = 0, tau = 0;
    for (const RunFigures& f : runs) {
        if (!std::isfinite(f.warm_v) || f.listed.empty() || f.listed[0].ratio <= 5.0) continue;
        ++n;
        if (!std::isfinite(f.got_v)) continue;
        ++named;
        amp += std::fabs(f.got_v - f.warm_v) <= 2.0 * f.got_v_se;
        tau += std::fabs(f.got_tau - f.warm_tau_s) <= 2.0 * f.got_tau_se;
    }
    std::printf(
        "single power-on exponential above 5x the floor: named %d of %d; amplitude within "
        "2 sigma %d, time constant within 2 sigma %d\n",
        named, n, amp, tau);
}

// Per clean scenario: othersim's plain "clean" carries its thermometer's lag (a real effect).
void Clean(const std::vector<RunFigures>& runs) {
    std::map<std::string, int> n, fp;
    std::map<std::string, std::map<std::string, int>> why;
    for (const RunFigures& f : runs) {
        if (f.group != "clean") continue;
        ++n[f.scenario];
        if (f.category == "adequate" || f.category == "named right alone") continue;
        ++fp[f.scenario];
        ++why[f.scenario][f.category + " (" + f.evidence + ")"];
    }
    if (n.empty()) std::printf("clean runs: 0 of 0 not adequate (nan %%)\n");
    for (const auto& [scenario, count] : n) {
        std::printf("%s runs: %d of %d not adequate (%.1f %%); the thresholds claim %.1f %%\n",
                    scenario.c_str(), fp[scenario], count, 100.0 * fp[scenario] / count,
                    100.0 * analysis::AnalysisOptions::Defaults().ClaimedFalsePositiveRate());
        for (const auto& [w, k] : why[scenario]) std::printf("  %d: %s\n", k, w.c_str());
    }
}

}  // namespace

void PrintSimulator(Simulator sim, const std::vector<RunFigures>& runs) {
    std::printf("\n## %s: %zu runs\n\n", Name(sim), runs.size());
    Confusion(runs);
    PerScenario(runs);
    Named(runs);
    Transfer(runs);
    Warmup(runs);
    Clean(runs);
    double s = 0;
    for (const RunFigures& f : runs) s += f.seconds;
    std::printf("mean time per run (calibration run, analysis, held-out run): %.2f s\n",
                s / std::max<size_t>(1, runs.size()));
}

}  // namespace gyrocal::bench
