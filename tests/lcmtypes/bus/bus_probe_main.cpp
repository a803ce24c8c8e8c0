// gyrocal-bus-probe: a test helper process for the bus layer's multi-process tests.
//   listen:  subscribes gyro_sample_t on a channel regex and reports its counters in STATUS
//            (received, decode_errors, seq_gaps) until SIGTERM or --idle-exit-s of silence;
//            --work-us-per-sample makes it a slow consumer (busy work per sample), for the flow
//            control tests (tests/lcmtypes/flow).
// Exit codes: 0 normal stop, 1 runtime failure (e.g. LCM cannot open), 2 bad options.
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>

#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/process/status.hpp"

int main(int argc, char** argv) {
    CLI::App app{"gyrocal-bus-probe: listen on a channel and report bus counters in STATUS"};
    std::string url;
    std::string channel_regex = "GYRO_.*";
    double idle_exit_s = 30.0;
    double work_us = 0.0;
    app.add_option("--lcm-url", url, "LCM URL (default: $GYROCAL_LCM_URL or the udpm default)");
    app.add_option("--channel", channel_regex, "channel regex to subscribe (gyro_sample_t)");
    app.add_option("--idle-exit-s", idle_exit_s, "exit after this long without messages")
        ->check(CLI::PositiveNumber);
    app.add_option("--work-us-per-sample", work_us, "busy work per sample [us] (a slow consumer)")
        ->check(CLI::Range(0.0, 1e6));
    app.footer("Exit codes: 0 stopped, 1 runtime failure, 2 bad options.");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    try {
        gyrocal::process::InstallStopHandlers();
        gyrocal::bus::Bus bus(gyrocal::bus::BusOptions{url});
        gyrocal::process::StatusReporter status(bus, "gyrocal-bus-probe",
                                                std::chrono::milliseconds(100));
        auto last = std::chrono::steady_clock::now();
        int64_t samples = 0;  // gyro samples alone (received also counts flow marks)
        bus.Subscribe<gyrocal::gyro_sample_t>(
            channel_regex, [&](const gyrocal::gyro_sample_t&, const std::string&) {
                last = std::chrono::steady_clock::now();
                status.SetExtra("samples", static_cast<double>(++samples));
                const auto until = last + std::chrono::duration<double, std::micro>(work_us);
                while (std::chrono::steady_clock::now() < until) {
                }
            });
        gyrocal::process::RunLoop(bus, status, [&] {
            return std::chrono::steady_clock::now() - last >
                   std::chrono::duration<double>(idle_exit_s);
        });
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-bus-probe: " << e.what() << "\n";
        return 1;
    }
}
