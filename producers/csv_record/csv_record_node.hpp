#pragma once
// The CSV recorder process: one row per gyro sample, in arrival order, with the encoder angle
// and chamber air temperature in force at the sample's time (csv/csv_writer.hpp). Samples that
// gyrocal-csv-source could not read back (non-finite gyro_v/temp_v, utime not after the
// sensor's previous one) are refused and counted in STATUS instead.
//
// Threads: one. Run() is RunLoop; handlers format and append to a buffered file, flushed once
// a second and at exit. It stops on SIGINT/SIGTERM, or after --idle-exit-s without messages.
// In-process (tests over memq://): publish on bus(), Handle it, then Finish() instead of Run().
#include <chrono>
#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "producers/csv/csv_writer.hpp"
#include "producers/csv/row_messages.hpp"

namespace gyrocal::csv_record {

struct CsvRecordOptions {
    std::string out;
    std::string lcm_url;
    std::vector<std::string> sensors;                     // empty = every GYRO_<id>
    int64_t time_origin_utime = csv::kDefaultStartUtime;  // [us] utime written as time_s = 0
    double idle_exit_s = 0.0;  // [s] of wall time without messages; 0 = never
    static CsvRecordOptions Defaults() { return {}; }
    std::string Validate() const;
};

class CsvRecordNode {
public:
    // Throws std::runtime_error when --out cannot be created.
    explicit CsvRecordNode(const CsvRecordOptions& options);
    // RunLoop until a stop, then Finish(): 0 on a normal stop, 1 when writing failed.
    int Run();
    // Flushes and closes the file and says how many rows it holds: 0, or 1 when writing failed.
    int Finish();

    // In-process use: the node's bus (publish to it, Handle it), its STATUS on demand.
    bus::Bus& bus() { return bus_; }
    void PublishStatus();
    int64_t rows_written() const { return rows_; }
    int64_t rejected() const { return status_.rejected(); }

private:
    using Clock = std::chrono::steady_clock;
    bool Idle();
    // Guard: a non-finite reading is refused (counted as `reject_key`); the series keeps its
    // last finite value.
    void KeepFinite(csv::LatestAt& series, int64_t utime, double value,
                    const std::string& reject_key, const std::string& field);

    CsvRecordOptions options_;
    std::ofstream out_;
    bus::Bus bus_;
    process::StatusReporter status_;
    csv::LatestAt encoder_deg_;
    csv::LatestAt chamber_c_;
    std::map<std::string, int64_t> power_on_utime_;  // [us] newest POWER_<id> per sensor
    std::optional<int64_t> PowerOn(const std::string& sensor_id) const;
    std::map<std::string, int64_t> last_utime_;  // [us] per sensor: rows only go forward
    int64_t rows_ = 0;
    int64_t last_received_ = 0;
    Clock::time_point last_activity_ = Clock::now();
    Clock::time_point last_flush_ = Clock::now();
};

}  // namespace gyrocal::csv_record
