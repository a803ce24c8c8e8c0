// gyrocal-line-source: publishes CSV lines streamed live by a DAQ or microcontroller (stdin, a
// serial device or a FIFO) as GYRO_<id>, ENCODER and CHAMBER_STATE messages.
#include <fcntl.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <iostream>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "producers/line_source/line_source_node.hpp"
#include "producers/producer_cli/producer_cli.hpp"

namespace {
constexpr const char* kFooter = R"(
Input: text lines; the first non-blank line is the header naming the columns (any order).
Required: time_s [s, strictly increasing per sensor], sensor_id, gyro_v [V], temp_v [V].
Optional: temp_c [degC] (else from temp_v via the transfer function), supply_v [V],
encoder_deg [deg], chamber_c [degC]. Unknown columns: one warning, then ignored. '#' lines
and blank lines are ignored; a repeat of the header line (a restarted DAQ) is ignored.
A tty given as --device is put in raw mode only; set its baud rate beforehand (stty).

Bad lines (missing/non-numeric/non-finite field, a line cut short, time_s not increasing,
an invalid sensor_id, > 64 KiB) are SKIPPED AND COUNTED, never published in part: a live
stream cannot stop. A warning naming STREAM:LINE and the column is printed at most once a
second (with the count suppressed); the count is in STATUS (rejected, lines_bad) and at exit.

--time stream: utime = --start-utime + time_s*1e6 (replays and exact timing);
--time wall:   utime = wall clock at reception [us since 1970] (live DAQs; time_s is still
               checked but only orders the data).

--flow (a file or a pipe, not a live DAQ): lines are read only while every gyrocal process on the
bus keeps up (each answers the source's FLOW_MARK messages once handled; --flow-window-kb
unanswered at most per consumer; one silent for --flow-timeout-s is no longer waited for).

Exit codes: 0 end of input or SIGINT/SIGTERM; 1 read error or a stream whose first line is
not a valid header; 2 bad options (out-of-range value, unknown preset, unopenable --device).)";
}  // namespace

int main(int argc, char** argv) {
    using namespace gyrocal;
    line_source::LineSourceOptions o = line_source::LineSourceOptions::Defaults();
    CLI::App app{"gyrocal-line-source: publish a live CSV line stream onto the gyrocal bus"};
    producer_cli::AddOpeningOptions(app, kFooter, "--device", o.device,
                                    "serial device or FIFO to read (default: stdin)", false,
                                    o.lcm_url);
    std::string time = "stream";
    app.add_option("--time", time, "stream|wall: where utime comes from (default stream)");
    producer_cli::AddConversionOptions(
        app, o.conversion, "utime [us] of time_s = 0 with --time stream (default 1e15), 0..4e18");
    app.add_option("--drain-s", o.drain_s, "wait after end of input before exit [s] (default 0.2)");
    app.add_flag("--flow", o.flow,
                 "not a live stream: read only as fast as every consumer keeps up (flow control; "
                 "a fast writer is held back by its pipe); needs --time stream");
    process::AddSourceFlowOptions(app, o.flow_options);
    const auto validate = [&] {
        const std::string err = producer_cli::Choose("--time", time,
                                                     {{"stream", line_source::TimeSource::kStream},
                                                      {"wall", line_source::TimeSource::kWall}},
                                                     o.time);
        return err.empty() ? o.Validate() : err;
    };
    if (auto exit_code =
            process::ParseCommandLine(app, argc, argv, "gyrocal-line-source", validate))
        return *exit_code;
    process::InstallStopHandlers();  // before a FIFO open that may wait for its writer
    int fd = 0;
    std::string name = "stdin";
    if (!o.device.empty()) {
        fd = open(o.device.c_str(), O_RDONLY | O_NOCTTY | O_CLOEXEC);
        if (fd < 0) {
            if (errno == EINTR && process::StopRequested()) return 0;
            process::PrintError("gyrocal-line-source",
                                "--device '" + o.device +
                                    "' cannot be opened: " + std::strerror(errno) +
                                    "; give a readable serial device, FIFO or file");
            return 2;
        }
        name = o.device;
    }
    try {
        line_source::LineSourceNode node(o, std::make_unique<line_source::LineInput>(fd, name));
        return node.Run();
    } catch (const std::exception& e) {
        process::PrintError("gyrocal-line-source", e.what());
        return 1;
    }
}
