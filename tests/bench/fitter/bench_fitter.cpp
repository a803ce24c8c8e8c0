// The fit on every still window off the receive path (issue 29): what it costs to keep, and how
// long a sample waits while a refit runs. Not a test: it prints figures and the machine.
//
//   gyrocal_bench_fitter [HOURS_MEMORY] [MSGS_PER_S] [UNITS]
//
// 1. Memory per unit-hour, one unit at 100 Hz with the encoder at 100 Hz (HOURS_MEMORY of a
//    triangle 25 -> -15 -> 55 -> 25 degC ramp, default 1): the heap the ramp fitter held before
//    this change (every raw sample and encoder reading in vectors: exactly its containers) and
//    the incremental bins now (RampFitter), both measured as the growth of the allocator's bytes in
//    use (mallinfo2) while the run is fed in.
// 2. Receive latency while refits run: a publisher thread sends UNITS units' run (default 4; 10 Hz,
//    2.3 h of data, encoder at 1 Hz) over LCM udpm (port 7940, TTL 0; run it inside a network
//    namespace: /work/bin/nsrun NAME ...) at MSGS_PER_S (default 2000: ~200x real time); the
//    receiving thread runs the ramp fitter (refit every 600 s of data once 1200 s are in) either
//    with the fit in the sample's handler (as the ramp fitter did before this change) or on the fit
//    worker (fit_worker.hpp). A second subscriber on the same thread takes the time from each
//    sample's publication to its dispatch: while a fit runs in the handler, nothing is dispatched.
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/fitter/node/fitter_node.hpp"
#include "processors/fitter/ramp_fitter.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/bench/support/machine.hpp"

namespace gyrocal {
namespace {

using Clock = std::chrono::steady_clock;
constexpr const char* kUrl = "udpm://239.255.76.67:7940?ttl=0&recv_buf_size=4194304";

struct Sample {
    analysis::GyroSample g;
    bool encoder = false;  // an encoder reading goes with it
};

// Triangle 25 -> -15 -> 55 -> 25 degC at 1 degC/min, table still, offset quadratic + white noise.
std::vector<Sample> Triangle(double hz, double encoder_hz, double max_s) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> n(0.0, 1e-3);
    std::vector<Sample> out;
    const double rate = 1.0 / 60.0, legs[] = {40.0 / rate, 70.0 / rate, 30.0 / rate};
    double t_c = 25.0, t_s = 0.0;
    int64_t seq = 0;
    const auto every = static_cast<int64_t>(std::llround(hz / encoder_hz));
    for (int leg = 0; leg < 3; ++leg)
        for (double s = 0; s < legs[leg] && t_s < max_s; s += 1.0 / hz, t_s += 1.0 / hz) {
            t_c += (leg == 1 ? 1.0 : -1.0) * rate / hz;
            const double d = t_c - 25.0;
            const auto u = static_cast<int64_t>(std::llround(t_s * 1e6)) + 1'000'000;
            out.push_back({{.utime = u,
                            .seq = seq,
                            .gyro_v = 2.5 + 5e-4 * d - 3e-6 * d * d + n(rng),
                            .temp_c = t_c,
                            .supply_v = 5.0},
                           seq % every == 0});
            ++seq;
        }
    return out;
}

// Bytes in use: the arena's and the mmapped blocks (large vectors are mmapped).
size_t HeapInUse() {
    const auto m = mallinfo2();
    return m.uordblks + m.hblkhd;
}

void Memory(double hours) {
    const std::vector<Sample> run = Triangle(100.0, 100.0, hours * 3600.0);
    const double h = 1e-6 * static_cast<double>(run.back().g.utime - run.front().g.utime) / 3600.0;
    size_t before = 0, after = 0, counted = 0;
    {
        const size_t h0 = HeapInUse();
        std::vector<analysis::GyroSample> samples;  // the ramp fitter's containers before
        std::vector<motion::EncoderReading> encoder;
        for (const Sample& s : run) {
            samples.push_back(s.g);
            if (s.encoder) encoder.push_back({s.g.utime, 0, 20000});
        }
        before = HeapInUse() - h0;
    }
    {
        const size_t h0 = HeapInUse();
        fitter::RampFitter f(fitter::RampFitterOptions::Defaults());
        f.StartRun("bench");
        for (const Sample& s : run) {
            if (s.encoder) f.AddEncoder({s.g.utime, 0, 20000});
            f.AddGyro("U1", s.g);
        }
        after = HeapInUse() - h0;
        counted = f.MemoryBytes();
    }
    std::printf("memory, 1 unit at 100 Hz + encoder at 100 Hz, %.2f h (%zu samples):\n", h,
                run.size());
    std::printf("  before (every raw sample and reading kept):  %7.2f MB per unit-hour\n",
                before / h / 1e6);
    std::printf(
        "  after  (incremental 10 s bins):               %7.3f MB per unit-hour (the bins count "
        "%.3f)\n",
        after / h / 1e6, counted / h / 1e6);
}

// Resets the peak resident size (VmHWM) to the current one (proc(5), clear_refs "5").
void ResetPeak() {
    if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        std::fputs("5", f);
        std::fclose(f);
    }
}

// 3. A day-long unit: what the bins hold and what one fit over them needs. One unit at 100 Hz, a
// triangle 25 -> -15 -> 55 -> 25 degC at 0.144 degC/min repeated (the day run's ramp rate), the
// table still; after each `hours` of data, one fit (the final fit's work) with its peak resident
// size above the resident size before it (VmHWM reset through clear_refs), and the heap in use
// after it (what a fit leaves behind: nothing, when the fit frees what it took).
void FitMemory(const std::vector<int>& hours) {
    std::printf("\nfit memory, 1 unit at 100 Hz, ramp 0.144 degC/min, still table:\n");
    std::printf("  %6s %10s %10s %12s %12s %10s %8s\n", "hours", "bins MB", "heap MB",
                "fit peak MB", "after fit MB", "fit s", "terms");
    fitter::RampFitter f(fitter::RampFitterOptions::Defaults());
    f.StartRun("bench");
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n(0.0, 1e-3);
    const double rate_c_per_s = 0.144 / 60.0, hz = 100.0;
    double t_c = 25.0, dir = -1.0;
    int64_t seq = 0;
    const size_t heap0 = HeapInUse();
    for (const int h : hours) {
        for (; seq < static_cast<int64_t>(h * 3600.0 * hz); ++seq) {
            t_c += dir * rate_c_per_s / hz;
            if (t_c < -15.0) dir = 1.0;
            if (t_c > 55.0) dir = -1.0;
            const double d = t_c - 25.0;
            const int64_t u = 1'000'000 + seq * 10'000;
            if (seq % 100 == 0) f.AddEncoder({u, 0, 20000});
            f.AddGyro("U1", {.utime = u,
                             .seq = seq,
                             .gyro_v = 2.5 + 5e-4 * d - 3e-6 * d * d + n(rng),
                             .temp_c = t_c,
                             .supply_v = 5.0});
        }
        const size_t heap = HeapInUse() - heap0;
        ResetPeak();
        const int64_t rss_kb = bench::ReadProcStats(getpid()).rss_kb;
        const auto t0 = Clock::now();
        const fitter::RampFitResult r = f.Fit("U1", 1'000'000 + seq * 10'000, true);
        const double s = std::chrono::duration<double>(Clock::now() - t0).count();
        const int64_t peak_kb = bench::ReadProcStats(getpid()).hwm_kb;
        const size_t after = HeapInUse() - heap0;
        std::printf("  %6d %10.1f %10.1f %12.1f %12.1f %10.2f %8zu  %s\n", h, f.MemoryBytes() / 1e6,
                    heap / 1e6, (peak_kb - rss_kb) / 1e3, after / 1e6, s,
                    r.set ? r.set->offset.term_names.size() : 0,
                    r.set ? "" : r.report.reason.substr(0, 100).c_str());
    }
}

struct Latency {
    std::vector<double> ms;
    int fits = 0;
    double max_fit_s = 0.0;
};

double Percentile(std::vector<double> v, double p) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size())))];
}

// One pass of the run through the bus, for `units` units (the same data under each id), with the
// fit in the handler (`inline_fit`) or on the worker.
Latency Pass(const std::vector<Sample>& run, double msgs_per_s, int units, bool inline_fit) {
    bus::Bus bus(bus::BusOptions{kUrl});
    process::StatusReporter status(bus, "bench-fitter");
    fitter::RampFitter f(fitter::RampFitterOptions::Defaults());
    std::optional<fitter::node::StillFitChannel> channel;
    Latency out;
    int64_t now = 0;
    auto unit_of = [](const std::string& ch) {
        return channels::SensorOf(channels::kGyroPrefix, ch).value();
    };
    if (inline_fit) {
        bus.Subscribe<gyro_sample_t>(channels::AllSensors(channels::kGyroPrefix),
                                     [&](const gyro_sample_t& m, const std::string& ch) {
                                         f.AddGyro(unit_of(ch), motion::GyroSampleOf(m));
                                         if (m.utime <= now) return;
                                         now = m.utime;
                                         for (const auto& r : f.OnTime(m.utime)) {  // the fit, here
                                             if (r.set)
                                                 bus.Publish(channels::Coeffs(r.sensor_id), *r.set);
                                             ++out.fits;
                                         }
                                     });
        bus.Subscribe<encoder_sample_t>(std::string(channels::kEncoder),
                                        [&](const encoder_sample_t& m, const std::string&) {
                                            f.AddEncoder({m.utime, m.counts, m.counts_per_rev});
                                        });
    } else {
        channel.emplace(bus, status, f);
    }
    const size_t total = run.size() * static_cast<size_t>(units);
    std::vector<std::atomic<int64_t>> sent(total);  // [ns] of the steady clock, per message
    std::atomic<bool> done{false};
    bus.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [&](const gyro_sample_t& m, const std::string&) {
            const auto k = static_cast<size_t>(m.seq);
            if (k < total)
                out.ms.push_back(
                    1e-6 *
                    static_cast<double>(Clock::now().time_since_epoch().count() - sent[k].load()));
        });
    f.StartRun("bench");
    std::thread pub([&] {
        bus::Bus p(bus::BusOptions{kUrl});
        const auto start = Clock::now();
        int64_t k = 0;
        for (size_t i = 0; i < run.size(); ++i) {
            const Sample& s = run[i];
            if (s.encoder) {
                std::this_thread::sleep_until(start +
                                              std::chrono::duration<double>(k++ / msgs_per_s));
                encoder_sample_t e{};
                e.utime = s.g.utime, e.encoder_id = "TABLE", e.seq = k, e.counts = 0,
                e.counts_per_rev = 20000;
                p.Publish(std::string(channels::kEncoder), e);
            }
            for (int u = 0; u < units; ++u) {
                std::this_thread::sleep_until(start +
                                              std::chrono::duration<double>(k++ / msgs_per_s));
                const std::string id = "U" + std::to_string(u + 1);
                gyro_sample_t g{};
                g.utime = s.g.utime, g.sensor_id = id, g.seq = s.g.seq * units + u,
                g.temp_c = s.g.temp_c;
                g.gyro_v = s.g.gyro_v, g.supply_v = s.g.supply_v;
                sent[static_cast<size_t>(g.seq)] = Clock::now().time_since_epoch().count();
                p.Publish(channels::Gyro(id), g);
            }
        }
        done = true;
    });
    while (!done || out.ms.size() < total) {
        if (!bus.Handle(std::chrono::milliseconds(20)) && done) break;
        if (channel) out.fits += static_cast<int>(channel->Publish());
    }
    pub.join();
    if (channel) {
        channel->worker().WaitIdle(std::chrono::minutes(5));
        out.fits += static_cast<int>(channel->Publish());
    }
    return out;
}

void Receive(double msgs_per_s, int units) {
    const std::vector<Sample> run = Triangle(10.0, 1.0, 1e9);
    std::printf(
        "\nreceive latency, %d units at 10 Hz + encoder at 1 Hz, %.2f h of data at %.0f messages/s "
        "(refit every 600 s of data):\n",
        units, 1e-6 * static_cast<double>(run.back().g.utime) / 3600.0, msgs_per_s);
    std::printf("  %-34s %6s %9s %9s %9s %9s %9s\n", "fit", "fits", "p50 ms", "p99 ms", "p99.9 ms",
                "max ms", "samples");
    for (const bool inline_fit : {true, false}) {
        const Latency l = Pass(run, msgs_per_s, units, inline_fit);
        std::printf("  %-34s %6d %9.3f %9.3f %9.3f %9.1f %9zu\n",
                    inline_fit ? "in the handler (before)" : "on the fit worker (after)", l.fits,
                    Percentile(l.ms, 0.5), Percentile(l.ms, 0.99), Percentile(l.ms, 0.999),
                    Percentile(l.ms, 1.0), l.ms.size());
    }
}

}  // namespace
}  // namespace gyrocal

int main(int argc, char** argv) {
    const int hours = gyrocal::bench::IntArg(argc, argv, 1, 1);
    const int rate = gyrocal::bench::IntArg(argc, argv, 2, 2000);
    const int units = gyrocal::bench::IntArg(argc, argv, 3, 4);
    if (hours < 1 || hours > 48 || rate < 100 || rate > 100000 || units < 1 || units > 16)
        return gyrocal::bench::Usage(argv,
                                     "[HOURS_MEMORY 1..48] [MSGS_PER_S 100..100000] [UNITS 1..16]");
    gyrocal::bench::PrintContext(argc, argv);
    if (const char* fm = std::getenv("BENCH_FIT_MEMORY_ONLY"); fm && *fm) {
        gyrocal::FitMemory({3, 6, 12, 24});
        return 0;
    }
    gyrocal::Memory(hours);
    gyrocal::Receive(rate, units);
    gyrocal::FitMemory({3, 6, 12, 24});
    return 0;
}
