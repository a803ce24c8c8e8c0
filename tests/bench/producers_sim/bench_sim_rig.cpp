// Samples generated per second by the simulated rig library alone (no LCM): 1, 4 and 16 units at
// 100 Hz with the default models (noise, thermal, supply, ADC, encoder, chamber), effects off and
// all six on. items_per_second = gyro samples/s (all units); sim_x = simulated seconds per
// second of CPU, i.e. the --speed the library alone could sustain.
// Run: <build>/bin/gyrocal_bench_sim_rig
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>
#include <thread>

#include "producers/sim/rig.hpp"
#include "tests/bench/support/bench_context.hpp"

namespace {

class CountingSink : public gyrocal::sim::RigSink {
public:
    int64_t gyro = 0;
    double checksum = 0.0;
    void OnGyro(const gyrocal::sim::GyroReading& r, const gyrocal::sim::GyroTruth&) override {
        ++gyro;
        checksum += r.gyro_v;
    }
};

void BM_SimRig(benchmark::State& state) {
    gyrocal::sim::RigConfig c = gyrocal::sim::RigConfig::Defaults();
    c.num_units = static_cast<int>(state.range(0));
    if (state.range(1) != 0) {
        for (const auto& name : gyrocal::sim::EffectNames()) {
            gyrocal::sim::SetEffect(c.effects, name, 1e-3 * (name == "temp_cubic" ? 1e-5 : 1.0));
        }
    }
    gyrocal::sim::Rig rig(c);
    rig.ChamberCommand(1, 60.0, 0.0);
    CountingSink sink;
    const int64_t chunk_us = 10'000'000;  // 10 simulated seconds per iteration
    int64_t t = c.start_utime;
    for (auto _ : state) {
        t += chunk_us;
        rig.RunUntil(t, sink);
    }
    benchmark::DoNotOptimize(sink.checksum);
    state.SetItemsProcessed(sink.gyro);
    state.counters["sim_x"] = benchmark::Counter(static_cast<double>(state.iterations()) * 10.0,
                                                 benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimRig)
    ->ArgNames({"units", "effects"})
    ->Args({1, 0})
    ->Args({4, 0})
    ->Args({16, 0})
    ->Args({4, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
    // The header block (bench_context.hpp) as Google Benchmark's custom context: it prints it
    // with its own header (on stderr) and writes it into --benchmark_format=json's "context".
    for (const auto& [key, value] : gyrocal::bench::ReadContext(argc, argv))
        benchmark::AddCustomContext(key, value);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
