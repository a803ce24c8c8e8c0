// Benchmark (not a test): the false-positive rate of the analysis on clean simulated runs (the
// rig's own effects off, nothing outside the list), over many seeds: how many are not "adequate",
// and, per channel of the generic features (time, temperature, supply, chamber air, encoder), on
// how many runs one of its features explained held-out data and the largest fraction of the
// held-out squared residual one of them removed (the margin to min_feature_drop). The run
// generator is the analysis tests' (tests/processors/analysis/sim_run.cpp), as in
// analysis_verdict_tests' clean-run test (seeds 701..740 there).
// Usage: gyrocal_bench_clean_runs [seeds 1..1000] [first seed] (default 100 from 1001).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "processors/analysis/analyze.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/processors/analysis/sim_run.hpp"

using namespace gyrocal;

namespace {

// The channel group of a feature: "encoder: table angle" -> "encoder".
std::string Group(const std::string& channel) {
    const size_t colon = channel.find(':');
    if (channel.rfind("chamber air", 0) == 0) return "chamber air";
    return colon == std::string::npos ? channel : channel.substr(0, colon);
}

struct GroupStats {
    int explained_runs = 0;
    double max_drop = -INFINITY;
    std::string max_feature;
};

}  // namespace

int main(int argc, char** argv) {
    const int seeds = bench::IntArg(argc, argv, 1, 100);
    const int first = bench::IntArg(argc, argv, 2, 1001);
    if (seeds < 1 || seeds > 1000 || first < 1)
        return bench::Usage(argv, "[seeds 1..1000] [first seed >= 1]");
    bench::PrintContext(argc, argv);
    std::map<std::string, int> outcomes;
    std::map<std::string, GroupStats> groups;
    for (int k = 0; k < seeds; ++k) {
        analysis::testing::SimRunOptions o;
        o.seed = static_cast<uint64_t>(first + k);
        const analysis::SensorResult r = analysis::Analyze(analysis::testing::MakeSimRun(o).run);
        ++outcomes[analysis::ToString(r.outcome)];
        std::map<std::string, bool> explained;
        for (const analysis::FeatureResult& f : r.features) {
            GroupStats& g = groups[Group(f.channel)];
            if (f.explains_heldout) explained[Group(f.channel)] = true;
            if (std::isfinite(f.heldout_drop) && f.heldout_drop > g.max_drop)
                g.max_drop = f.heldout_drop, g.max_feature = f.feature;
        }
        for (const auto& [name, yes] : explained) groups[name].explained_runs += yes ? 1 : 0;
        if (r.outcome != analysis::Outcome::kAdequate)
            std::printf("seed %d: %s: %s\n", first + k, analysis::ToString(r.outcome),
                        r.headline.c_str());
    }
    std::printf("clean runs: %d seeds from %d\n", seeds, first);
    for (const auto& [name, n] : outcomes)
        std::printf("  %-22s %4d (%.1f %%)\n", name.c_str(), n, 100.0 * n / seeds);
    std::printf("%-22s %16s %16s  %s\n", "feature channel", "runs explained", "largest drop",
                "(feature; threshold min_feature_drop)");
    for (const auto& [name, g] : groups)
        std::printf("%-22s %16d %16.3f  (%s; %.2f)\n", name.c_str(), g.explained_runs, g.max_drop,
                    g.max_feature.c_str(), analysis::AnalysisOptions::Defaults().min_feature_drop);
    return 0;
}
