// gyrocal-csv-source: publishes a measured-data CSV file as GYRO_<id>, ENCODER and
// CHAMBER_STATE messages, the same messages a rig sends. See README.md.
#include <CLI/CLI.hpp>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "producers/csv_source/csv_source_node.hpp"
#include "producers/producer_cli/producer_cli.hpp"

namespace {

constexpr const char* kFooter = R"(
CSV: a header row names the columns, in any order. Required: time_s [s, strictly increasing
per sensor], sensor_id, gyro_v [V], temp_v [V]. Optional: temp_c [degC] (else computed from
temp_v with the transfer function), supply_v [V], encoder_deg [deg, cumulative table angle],
chamber_c [degC, chamber air]. Unknown columns are ignored with one warning. Rows of several
sensors may interleave. Blank lines and lines starting with '#' are ignored; an empty optional
field means "not measured".

Bad rows (missing or non-numeric field, NaN/inf, a line cut short, time_s not increasing for
its sensor, an invalid sensor_id) are reported as FILE:LINE: column NAME: problem; valid form.
The whole file is read and checked BEFORE anything is published:
  --on-error stop (default): the first bad row ends the command with exit 1, nothing published.
  --on-error skip: bad rows are dropped whole (never half a sample) and counted; the count is
                   in STATUS (rows_skipped_bad) and in the exit summary.

Messages: each row -> gyro_sample_t on GYRO_<sensor_id> (seq per sensor from 0,
utime = --start-utime + time_s*1e6, has_adc false, supply_v NaN when absent); encoder_deg ->
encoder_sample_t on ENCODER (one per distinct time, counts = angle * counts-per-rev / 360);
chamber_c -> chamber_state_t on CHAMBER_STATE at most once per second of data time (setpoint_c
NaN: a file has no setpoint). Encoder/chamber are published before the gyro sample of a row.

Pacing: --speed X replays X data seconds per wall second. --max publishes as fast as every
consumer keeps up (flow control: each gyrocal process answers the source's FLOW_MARK messages
once it has handled them, and the source keeps at most --flow-window-kb unanswered per consumer,
so none can overflow its socket buffer; a consumer silent for --flow-timeout-s is no longer
waited for, and said so). When no process answers, --max falls back to --max-rate-hz messages/s
(default 20000) in 2 ms batches. lcm-logger and lcm-spy do not answer: lcm-logger 1.3.1 drops
beyond a 30-message queue, so when it records, use --speed. --batch-samples N sends N samples
of a channel per message (gyro_batch_t, encoder_batch_t); every gyrocal process unpacks them.

Exit codes: 0 file done (after --drain-s) or stopped by SIGINT/SIGTERM; 1 malformed file
(stop policy) or publish failure; 2 bad options (unknown option, out-of-range value, missing
or unreadable file). With --check-rows: 0 valid, 1 malformed (or no data row), 2 unreadable.)";

}  // namespace

int main(int argc, char** argv) {
    using namespace gyrocal;
    csv_source::CsvSourceOptions o = csv_source::CsvSourceOptions::Defaults();
    CLI::App app{"gyrocal-csv-source: replay a measured-data CSV file onto the gyrocal bus"};
    producer_cli::AddOpeningOptions(app, kFooter, "file,--file", o.file, "CSV file to replay", true,
                                    o.lcm_url);
    process::AddPacingOptions(app, o.speed, o.max,
                              "data seconds per wall second, > 0 (default 1 = real time)");
    app.add_option("--max-rate-hz", o.max_rate_hz,
                   "--max when no consumer answers: message-rate cap [msg/s], 1..1e7 "
                   "(default 20000)");
    process::AddSourceFlowOptions(app, o.flow);
    std::string on_error = "stop";
    app.add_option("--on-error", on_error, "stop|skip: what a bad row does (default stop)");
    producer_cli::AddConversionOptions(app, o.conversion,
                                       "utime [us] of time_s = 0 (default 1e15), 0..4e18");
    app.add_option("--drain-s", o.drain_s, "wait after the last row before exit [s] (default 0.5)");
    app.add_option("--check-rows", o.check_rows,
                   "only check the header and the first N rows, publish nothing, exit 0 valid or "
                   "1 malformed (gyrocal calibrate's check before a run), 0..1e9")
        ->check(CLI::Range(0L, 1000000000L));
    const auto validate = [&] {
        const std::string err = producer_cli::Choose(
            "--on-error", on_error, {{"stop", csv::OnError::kStop}, {"skip", csv::OnError::kSkip}},
            o.on_error);
        return err.empty() ? o.Validate() : err;
    };
    if (auto exit_code = process::ParseCommandLine(app, argc, argv, "gyrocal-csv-source", validate))
        return *exit_code;
    return csv_source::ReplayCsvFile(o);
}
