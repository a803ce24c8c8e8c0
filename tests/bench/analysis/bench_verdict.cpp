// Benchmark (not a test): does the analysis' verdict hold on data shaped unlike our simulators?
// On the project's rig and on othersim (an independent rig, tests/support/othersim), many seeds of
// every scenario of verdict_scenarios.hpp (clean, each listed effect, effects outside the list,
// power-on transients, a one-time shift, combinations), each effect at a random size. Per run:
// the analysis on the calibration run, then the stored extended model applied to a second run of
// the same unit (same simulator and profile, fresh noise, starting at power-on, the same effects)
// beside the unit's true model at the measured temperature on the same samples.
// Printed: the confusion table per simulator and group, the share of listed effects named when
// above 5x the floor (masked ones included), held-out error over the true model's, the warm-up's
// amplitude and time constant against the truth, the clean false-positive rate against the rate
// the thresholds claim, and the machine, date and time per run.
// Sizes: an effect's size is the RMS over the calibration run's still bins of its offset after
// projecting out the declared quadratic (what the analysis can possibly see), over the run's
// floor (the analysis' 10 s-bin Allan deviation of its residual).
// Usage: gyrocal_bench_verdict [runs per scenario] [clean runs] [threads] [rig|othersim|both]
// (defaults 10, 60, 2, both). Environment (development aids): VERDICT_VERBOSE=1 prints a line per
// run, VERDICT_DUMP=1 the residual bins beyond 3.5x the floor of every run not adequate,
// VERDICT_SCENARIO=text runs only the scenarios whose name holds it ("a;b": a or b, "=name":
// that scenario alone), VERDICT_WINDOWS_STATISTIC=
// plugin|studentised sets the windows test's statistic (default: the analysis' default).
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "tests/bench/analysis/verdict_run.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"

using namespace gyrocal;
using namespace gyrocal::bench;

namespace {

struct Job {
    Simulator sim;
    size_t scenario;
    uint64_t seed;
};

bool Selected(const std::string& name) {
    const char* only = std::getenv("VERDICT_SCENARIO");
    if (!only) return true;
    const std::string all = only;
    for (size_t a = 0; a <= all.size();) {
        size_t e = all.find(';', a);
        if (e == std::string::npos) e = all.size();
        const std::string part = all.substr(a, e - a);
        const bool exact = !part.empty() && part[0] == '=';
        if (exact && name == part.substr(1)) return true;
        if (!exact && !part.empty() && name.find(part) != std::string::npos) return true;
        a = e + 1;
    }
    return false;
}

std::vector<Job> Jobs(int per_scenario, int clean, const std::string& which) {
    std::vector<Job> jobs;
    for (Simulator s : {Simulator::kRig, Simulator::kOthersim}) {
        if (which != "both" && which != Name(s)) continue;
        for (size_t k = 0; k < Scenarios().size(); ++k) {
            // VERDICT_SCENARIO=text: only the scenarios whose name holds it (a development aid);
            // "a;b": those that hold a or b. "=name": only the scenario called name.
            if (!Selected(Scenarios()[k].name)) continue;
            if (Scenarios()[k].othersim_only && s != Simulator::kOthersim) continue;
            const int n = Scenarios()[k].group == "clean" ? clean : per_scenario;
            for (int i = 0; i < n; ++i)
                jobs.push_back({s, k, static_cast<uint64_t>(5000 + 1000 * k + i)});
        }
    }
    return jobs;
}

std::vector<RunFigures> RunAll(const std::vector<Job>& jobs, int threads) {
    std::vector<RunFigures> out(jobs.size());
    std::atomic<size_t> next{0}, done{0};
    auto work = [&] {
        for (size_t i; (i = next++) < jobs.size();) {
            out[i] = RunOne(jobs[i].sim, Scenarios()[jobs[i].scenario], jobs[i].seed);
            const size_t d = ++done;
            if (d % 25 == 0) std::fprintf(stderr, "  %zu of %zu runs\n", d, jobs.size());
        }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(work);
    for (std::thread& t : pool) t.join();
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    const int per = IntArg(argc, argv, 1, 10), clean = IntArg(argc, argv, 2, 60);
    const int threads = IntArg(argc, argv, 3, 2);
    const std::string which = argc > 4 ? argv[4] : "both";
    if (per < 0 || clean < 0 || threads < 1 || threads > 64 ||
        (which != "both" && which != "rig" && which != "othersim"))
        return Usage(argv,
                     "[runs per scenario >= 0] [clean runs >= 0] [threads 1..64] "
                     "[rig|othersim|both]");
    gyrocal::bench::PrintContext(argc, argv);
    const std::vector<Job> jobs = Jobs(per, clean, which);
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<RunFigures> figs = RunAll(jobs, threads);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (Simulator s : {Simulator::kRig, Simulator::kOthersim}) {
        std::vector<RunFigures> mine;
        for (size_t i = 0; i < jobs.size(); ++i)
            if (jobs[i].sim == s) mine.push_back(figs[i]);
        if (!mine.empty()) PrintSimulator(s, mine);
    }
    std::printf("\n%zu runs in %.0f s wall on %d threads (%.2f s per run and thread)\n",
                jobs.size(), wall, threads, wall * threads / std::max<size_t>(1, jobs.size()));
    return 0;
}
