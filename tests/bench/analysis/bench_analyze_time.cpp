// Benchmark (not a test): wall and CPU time of Analyze() (bins, selection, held-out gate, generic
// features beyond the list, residual diagnostics, verdict) on one long simulated run of about
// 1.5 M samples, plus BuildSensorRun (still/moving, power-on) and the chamber air for the same
// run. Prints the date, commit, machine and its load first (tests/bench/support/bench_context.hpp).
// Usage: gyrocal_bench_analyze_time [repeats 1..20] (default 3; the figure is the median).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/processors/analysis/sim_run.hpp"

using namespace gyrocal;

namespace {

double CpuS() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
    const int repeats = bench::IntArg(argc, argv, 1, 3);
    if (repeats < 1 || repeats > 20) return bench::Usage(argv, "[repeats 1..20]");
    bench::PrintContext(argc, argv);
    analysis::testing::SimRunOptions o;
    o.seed = 901;
    // 11 setpoints with 900 s dwells and 6 degC/min ramps: about 1.5 M samples at 100 Hz.
    o.setpoints_c = {-10, 50, 10, 70, 30, 60, 20, -5, 45, 15, 65};
    o.dwell_s = 900.0;
    const auto sim = analysis::testing::MakeSimRun(o, true);
    std::vector<double> build_s, analyze_s, analyze_cpu_s;
    analysis::SensorResult r;
    for (int k = 0; k < repeats; ++k) {
        auto t0 = std::chrono::steady_clock::now();
        analysis::SensorRun run =
            analysis::BuildSensorRun(sim.run.sensor_id, sim.raw, sim.encoder, sim.run.plateaus,
                                     sim.run.sensitivities, sim.power);
        analysis::AddChamberAir(run, sim.air);
        auto t1 = std::chrono::steady_clock::now();
        const double c0 = CpuS();
        r = analysis::Analyze(run);
        const double c1 = CpuS();
        auto t2 = std::chrono::steady_clock::now();
        build_s.push_back(std::chrono::duration<double>(t1 - t0).count());
        analyze_s.push_back(std::chrono::duration<double>(t2 - t1).count());
        analyze_cpu_s.push_back(c1 - c0);
    }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    std::printf(
        "gyrocal analyze timing: one simulated run, %zu samples, %d still bins, %d repeats\n",
        sim.raw.size(), r.n_bins, repeats);
    std::printf("%-28s %10s %10s\n", "step (median)", "wall_s", "cpu_s");
    std::printf("%-28s %10.3f %10s\n", "BuildSensorRun", median(build_s), "-");
    std::printf("%-28s %10.3f %10.3f\n", "Analyze", median(analyze_s), median(analyze_cpu_s));
    std::printf("%-28s %10.3f\n", "total", median(build_s) + median(analyze_s));
    std::printf("outcome: %s\n", analysis::ToString(r.outcome));
    return 0;
}
