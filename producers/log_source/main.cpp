// gyrocal-log-source: publishes an LCM log (lcm-logger's file) back onto the gyrocal bus, paced
// by its recorded time or by the consumers (flow control). See README.md.
#include <CLI/CLI.hpp>
#include <iostream>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "producers/log_source/log_source_node.hpp"
#include "producers/producer_cli/producer_cli.hpp"

namespace {

constexpr const char* kFooter = R"(
Every event of the log goes out on its channel with its bytes unchanged, in file order; events
on channels that --channels does not match, and the flow control of the recorded run
(FLOW_MARK, FLOW_ACK), are left out. The whole file is checked first (every event's sync word
and lengths): a damaged log publishes nothing and names the byte where it is damaged.

Pacing: --speed X replays X recorded seconds per wall second (by the time lcm-logger received
each event). --max publishes as fast as every consumer keeps up (flow control: each gyrocal
process answers the source's FLOW_MARK messages once handled; --flow-window-kb unanswered at most
per consumer; one silent for --flow-timeout-s is no longer waited for); with no process
answering, --max has no timing at all, as lcm-logplayer's fastest.

Exit codes: 0 file done (or stopped by SIGINT/SIGTERM); 1 damaged log (nothing published) or a
publish failure; 2 bad options (unknown option, out-of-range value, unreadable file).)";

}  // namespace

int main(int argc, char** argv) {
    using namespace gyrocal;
    log_source::LogSourceOptions o = log_source::LogSourceOptions::Defaults();
    CLI::App app{"gyrocal-log-source: publish an LCM log onto the gyrocal bus"};
    producer_cli::AddOpeningOptions(app, kFooter, "file,--file", o.file,
                                    "LCM log file (lcm-logger's)", true, o.lcm_url);
    process::AddPacingOptions(app, o.speed, o.max,
                              "recorded seconds per wall second, > 0 (default 1 = as recorded)");
    app.add_option("--channels", o.channels,
                   "regular expression of the channels to publish, the whole name (default .*)");
    app.add_option("--drain-s", o.drain_s,
                   "wait after the last event before exit [s] (default 0.5)");
    process::AddSourceFlowOptions(app, o.flow);
    app.remove_option(app.get_option("--batch-samples"));  // events go out as recorded
    if (auto exit_code = process::ParseCommandLine(app, argc, argv, "gyrocal-log-source",
                                                   [&] { return o.Validate(); }))
        return *exit_code;
    int64_t events = 0;
    try {
        events = log_source::CheckLog(o.file);
    } catch (const log_source::LogError& e) {
        std::cerr << "gyrocal-log-source: error: " << e.what()
                  << "\ngyrocal-log-source: nothing published\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-log-source: " << e.what() << "; give a readable LCM log file\n";
        return 2;
    }
    process::InstallStopHandlers();
    try {
        log_source::LogSourceNode node(o, events);
        return node.Run();
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-log-source: error: " << e.what() << "\n";
        return 1;
    }
}
