#pragma once
// The options every non-real-time source shares for flow control (lcmtypes/flow) and batching
// (lcmtypes/bus/batch.hpp): the same names, help texts, ranges and messages in the simulated rig,
// the CSV, line and log sources and `gyrocal replay`.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <string>

#include "lcmtypes/bus/batch.hpp"
#include "lcmtypes/flow/flow_window.hpp"

namespace gyrocal::process {

struct SourceFlowOptions {
    double window_kb = 2048;         // [KiB] unacknowledged buffer bytes per consumer
    double consumer_timeout_s = 10;  // [s] a consumer that stops answering is waited for so long
    int batch_samples = 1;           // samples per batch message; 1 = every sample alone
    static SourceFlowOptions Defaults() { return {}; }

    flow::WindowOptions Window() const {
        flow::WindowOptions w;
        w.window_bytes = static_cast<int64_t>(std::llround(window_kb * 1024));
        w.mark_every_bytes = w.window_bytes / 4;
        w.consumer_timeout_s = consumer_timeout_s;
        return w;
    }
    // "" or one line naming the option and its valid range.
    std::string Validate() const {
        if (!(window_kb >= 16 && window_kb <= 1 << 20))
            return "--flow-window-kb " + std::to_string(window_kb) +
                   " is out of range; valid: 16 to 1048576 KiB (the receivers' socket buffer, "
                   "8 MiB on the default URL, bounds what is safe: keep it below a quarter)";
        if (!(consumer_timeout_s >= 0.5 && consumer_timeout_s <= 3600))
            return "--flow-timeout-s " + std::to_string(consumer_timeout_s) +
                   " is out of range; valid: 0.5 to 3600 s";
        if (!(batch_samples >= 1 && batch_samples <= 512))
            return "--batch-samples " + std::to_string(batch_samples) +
                   " is out of range; valid: 1 to 512 (16 fits an Ethernet frame)";
        return "";
    }
};

inline constexpr const char* kMaxHelp = "as fast as every consumer keeps up (flow control)";

// A source's pacing: --speed (seconds of data per wall second; `speed_help` says whose) and --max
// (as fast as every consumer keeps up), which exclude each other. Returns --speed (to check its
// range).
inline CLI::Option* AddPacingOptions(CLI::App& app, double& speed, bool& max,
                                     const std::string& speed_help,
                                     const std::string& max_help = kMaxHelp) {
    CLI::Option* speed_option = app.add_option("--speed", speed, speed_help);
    app.add_flag("--max", max, max_help)->excludes(speed_option);
    return speed_option;
}

// Adds --flow-window-kb, --flow-timeout-s and --batch-samples (their defaults in the help).
inline void AddSourceFlowOptions(CLI::App& app, SourceFlowOptions& o) {
    app.add_option("--flow-window-kb", o.window_kb,
                   "flow control: buffer KiB a consumer may hold unanswered (default 2048)");
    app.add_option("--flow-timeout-s", o.consumer_timeout_s,
                   "flow control: a consumer silent this long is no longer waited for "
                   "(default 10)");
    app.add_option("--batch-samples", o.batch_samples,
                   "gyro/encoder samples per message (1 = alone; " +
                       std::to_string(bus::kDefaultBatchSamples) +
                       " fits an Ethernet frame) (default 1)");
}

}  // namespace gyrocal::process
