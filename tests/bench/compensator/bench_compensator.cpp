// Per-sample cost of the live compensator's arithmetic (no bus): SensorCompensator::Apply, the
// C++ class gyrocal-compensator runs per sample (input trackers, both models, rate, angle, and the
// rate's standard error from the coefficient covariances), and gyrocal_model.h's
// gyrocal_compensate alone (trackers, models, rate, angle: what the exported firmware code runs),
// each with the seed's quadratic models and with the extended set of every term kind
// (bench_inputs.hpp). The difference between the two is the C++ wrapper's overhead.
// Inputs: 100 Hz samples of a ramping, turning unit (bench_inputs.hpp), one 480 s temperature
// period replayed in a loop with utime always advancing by 10 ms. items_per_second = samples/s.
// Not a test: figures. Run: <build>/bin/gyrocal_bench_compensator
#include <benchmark/benchmark.h>

#include <string>

#include "processors/compensator/compensate.hpp"
#include "tests/bench/compensator/bench_inputs.hpp"
#include "tests/bench/support/bench_context.hpp"

namespace {

using gyrocal::bench::ModelKind;
using gyrocal::bench::RawSample;

constexpr double kRateHz = 100.0;
constexpr int64_t kPeriodUs = 10'000;                   // [us] 100 Hz
constexpr int64_t kStartUtime = 1'000'000'000'000'000;  // [us]

const std::vector<RawSample>& Stream() {
    static const std::vector<RawSample> stream = gyrocal::bench::SyntheticStream(
        0, kRateHz, static_cast<int64_t>(gyrocal::bench::kTempPeriodS * kRateHz));
    return stream;
}

// A sample that is not compensated would make the figure the cost of a refusal: say so instead.
void ReportRefusals(benchmark::State& state, int64_t refused, int64_t n) {
    if (refused > 0)
        state.SkipWithError(
            (std::to_string(refused) + " of " + std::to_string(n) + " samples not compensated")
                .c_str());
}

void BM_SensorCompensatorApply(benchmark::State& state, ModelKind kind) {
    namespace cp = gyrocal::compensator;
    cp::SensorCompensator comp;
    if (comp.SetCoefficients(gyrocal::bench::BenchSet(kind, "B01")).outcome !=
        cp::SetOutcome::kApplied) {
        state.SkipWithError("the benchmark's coefficient set was refused");
        return;
    }
    comp.PowerOn(kStartUtime);
    const std::vector<RawSample>& stream = Stream();
    const size_t n = stream.size();
    int64_t k = 0, refused = 0;
    for (auto _ : state) {
        const RawSample& x = stream[static_cast<size_t>(k) % n];
        const cp::ApplyResult r =
            comp.Apply({kStartUtime + k * kPeriodUs, k, x.gyro_v, x.temp_c, x.supply_v});
        refused += r.status != cp::ApplyStatus::kOk ? 1 : 0;
        benchmark::DoNotOptimize(r.out.rate_dps);
        benchmark::DoNotOptimize(r.out.rate_stderr_dps);
        ++k;
    }
    state.SetItemsProcessed(k);
    ReportRefusals(state, refused, k);
}

void BM_GyrocalCompensateC(benchmark::State& state, ModelKind kind) {
    namespace md = gyrocal::model;
    const md::CoeffSet set = gyrocal::bench::BenchSet(kind, "B01");
    const md::Evaluator off(set.offset), sens(set.sensitivity);
    const gyrocal_model_t off_c = off.CView(), sens_c = sens.CView();
    gyrocal_compensator_t comp;
    gyrocal_compensator_init(&comp, &off_c, &sens_c, GYROCAL_EXTRAPOLATE,
                             md::TrackerConfigFor({&set.offset, &set.sensitivity}));
    gyrocal_tracker_power_on(&comp.tracker, kStartUtime);
    const std::vector<RawSample>& stream = Stream();
    const size_t n = stream.size();
    int64_t k = 0, refused = 0;
    gyrocal_rate_t rate;
    for (auto _ : state) {
        const RawSample& x = stream[static_cast<size_t>(k) % n];
        refused += gyrocal_compensate(&comp, kStartUtime + k * kPeriodUs, x.gyro_v, x.temp_c,
                                      x.supply_v, &rate)
                       ? 0
                       : 1;
        benchmark::DoNotOptimize(rate.rate_dps);
        ++k;
    }
    state.SetItemsProcessed(k);
    ReportRefusals(state, refused, k);
}

BENCHMARK_CAPTURE(BM_SensorCompensatorApply, quadratic, ModelKind::kQuadratic);
BENCHMARK_CAPTURE(BM_SensorCompensatorApply, extended, ModelKind::kExtended);
BENCHMARK_CAPTURE(BM_GyrocalCompensateC, quadratic, ModelKind::kQuadratic);
BENCHMARK_CAPTURE(BM_GyrocalCompensateC, extended, ModelKind::kExtended);

}  // namespace

int main(int argc, char** argv) {
    // The header block (bench_context.hpp) as Google Benchmark's custom context: it prints it
    // with its own header (on stderr) and writes it into --benchmark_format=json's "context".
    for (const auto& [key, value] : gyrocal::bench::ReadContext(argc, argv))
        benchmark::AddCustomContext(key, value);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
