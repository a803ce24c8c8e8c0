// gyrocal-csv-record: writes gyro samples (with the encoder angle and chamber air temperature in
// force) to the measured-data CSV format that gyrocal-csv-source reads: for round trips, and
// for exporting runs to other labs.
#include <CLI/CLI.hpp>
#include <iostream>

#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "producers/csv_record/csv_record_node.hpp"
#include "producers/producer_cli/producer_cli.hpp"

namespace {
constexpr const char* kFooter = R"(
Output: header
time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,encoder_deg,chamber_c,time_since_power_s; one row
per gyro sample in arrival order. time_s = (utime - --time-origin-utime) / 1e6 with 6 decimals
(microsecond exact); values in the shortest form that reads back to the same double;
encoder_deg = latest ENCODER angle_deg with utime <= the sample's, chamber_c = latest
CHAMBER_STATE air_c likewise, time_since_power_s = (utime - the latest POWER_<id>
power_on_utime) / 1e6; an empty field when unknown (and supply_v when NaN).
Samples with non-finite gyro_v/temp_v, or utime not after the sensor's previous sample, are not
written (the file must read back): counted in STATUS rejected, warned at most once a second.

Stops on SIGINT/SIGTERM, or after --idle-exit-s seconds without any message; the file is
flushed once a second and at exit.

Exit codes: 0 normal stop; 1 runtime failure (cannot write, LCM failure); 2 bad options.)";
}  // namespace

int main(int argc, char** argv) {
    using namespace gyrocal;
    csv_record::CsvRecordOptions o = csv_record::CsvRecordOptions::Defaults();
    CLI::App app{"gyrocal-csv-record: record gyro samples to a measured-data CSV file"};
    producer_cli::AddOpeningOptions(app, kFooter, "--out", o.out, "CSV file to write (overwritten)",
                                    true, o.lcm_url);
    app.add_option("--sensors", o.sensors, "only these sensor ids, comma separated (default all)")
        ->delimiter(',');
    app.add_option("--time-origin-utime", o.time_origin_utime,
                   "utime [us] written as time_s = 0 (default 1e15)");
    app.add_option("--idle-exit-s", o.idle_exit_s,
                   "exit after this many seconds without messages; 0 = never (default 0)");
    if (auto exit_code = process::ParseCommandLine(app, argc, argv, "gyrocal-csv-record",
                                                   [&] { return o.Validate(); }))
        return *exit_code;
    process::InstallStopHandlers();
    try {
        csv_record::CsvRecordNode node(o);
        return node.Run();
    } catch (const std::runtime_error& e) {
        std::cerr << "gyrocal-csv-record: error: " << e.what() << "\n";
        // An --out that cannot be created is a configuration error.
        return std::string(e.what()).rfind("--out", 0) == 0 ? 2 : 1;
    }
}
