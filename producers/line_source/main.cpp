// gyrocal-line-source: publishes CSV lines streamed live by a DAQ or microcontroller (stdin, a
// serial device or a FIFO) as GYRO_<id>, ENCODER and CHAMBER_STATE messages.
#include <fcntl.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <iostream>

#include "bus/shutdown.hpp"
#include "line_source_node.hpp"

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

Exit codes: 0 end of input or SIGINT/SIGTERM; 1 read error or a stream whose first line is
not a valid header; 2 bad options (out-of-range value, unknown preset, unopenable --device).)";
}  // namespace

int main(int argc, char** argv) {
    using namespace gyrocal;
    LineSourceOptions o = LineSourceOptions::Defaults();
    CLI::App app{"gyrocal-line-source: publish a live CSV line stream onto the gyrocal bus"};
    app.footer(kFooter);
    app.add_option("--device", o.device, "serial device or FIFO to read (default: stdin)");
    app.add_option("--lcm-url", o.lcm_url,
                   "LCM URL (default $GYROCAL_LCM_URL, else udpm://239.255.76.67:7667?ttl=0)");
    std::string time = "stream";
    app.add_option("--time", time, "stream|wall: where utime comes from (default stream)");
    app.add_option("--start-utime", o.conversion.start_utime,
                   "utime [us] of time_s = 0 with --time stream (default 1e15), 0..4e18");
    app.add_option("--preset", o.conversion.preset,
                   "gyro module preset for the temperature transfer: 610|613 (default 610)");
    app.add_option("--temp-v-at-25c", o.conversion.temp_v_at_25c,
                   "temperature output at 25 degC [V] (preset: 2.5), -10..10");
    app.add_option("--temp-v-per-k", o.conversion.temp_v_per_k,
                   "temperature output slope [V/K] (preset: 0.009), > 0 and <= 1");
    app.add_option("--encoder-counts-per-rev", o.conversion.encoder_counts_per_rev,
                   "encoder counts per revolution incl. quadrature (default 20000), >= 1");
    app.add_option("--drain-s", o.drain_s, "wait after end of input before exit [s] (default 0.2)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "gyrocal-line-source: " << e.what() << " (see --help)\n";
        return 2;
    }
    if (time == "stream")
        o.time = TimeSource::kStream;
    else if (time == "wall")
        o.time = TimeSource::kWall;
    else {
        std::cerr << "gyrocal-line-source: --time '" << time
                  << "' is unknown; valid: stream or wall\n";
        return 2;
    }
    if (const std::string err = o.Validate(); !err.empty()) {
        std::cerr << "gyrocal-line-source: " << err << "\n";
        return 2;
    }
    InstallStopHandlers();  // before a FIFO open that may wait for its writer
    int fd = 0;
    std::string name = "stdin";
    if (!o.device.empty()) {
        fd = open(o.device.c_str(), O_RDONLY | O_NOCTTY | O_CLOEXEC);
        if (fd < 0) {
            if (errno == EINTR && StopRequested()) return 0;
            std::cerr << "gyrocal-line-source: --device '" << o.device
                      << "' cannot be opened: " << std::strerror(errno)
                      << "; give a readable serial device, FIFO or file\n";
            return 2;
        }
        name = o.device;
    }
    try {
        LineSourceNode node(o, std::make_unique<LineInput>(fd, name));
        return node.Run();
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-line-source: error: " << e.what() << "\n";
        return 1;
    }
}
