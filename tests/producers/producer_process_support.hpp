#pragma once
// Shared pieces of the measured-data producers' process tests (tests/producers/csv_source,
// csv_record, line_source, producer_cli): a scratch folder, the test's udpm URL, a synthetic
// measured-data CSV with known values, starting the executables, waiting for a process's first
// STATUS (it has subscribed by then), and comparing two CSV files sample by sample.
#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "producers/csv/csv_file.hpp"

namespace gyrocal::test {

std::string UdpmUrl(int port);
std::string Bin(const std::string& name);  // path of a built executable

// A fresh folder under the temp dir for one test; removed at destruction.
class Scratch {
public:
    explicit Scratch(const std::string& name);
    ~Scratch();
    std::string Path(const std::string& file) const { return (dir_ / file).string(); }

private:
    std::filesystem::path dir_;
};

struct SyntheticSpec {
    std::vector<std::string> sensors = {"S01", "S02", "S03"};
    double rate_hz = 100.0;
    double duration_s = 3.0;
    unsigned seed = 1;
};
// Writes a CSV with columns in a shuffled order and an unknown "operator" column: gyro_v =
// 2.5 V + per-unit offset + N(0, 2 mV), temp_v from a 1 K/s ramp plus N(0, 0.5 mV), supply_v
// on all but the last sensor (empty there), encoder_deg on every row (a 90 deg move from 1.0 s
// to 1.5 s), chamber_c constant within each whole second. Values carry 6 decimals.
// Returns the text lines after the header (to build bad files from).
std::vector<std::string> WriteSyntheticCsv(const std::string& path, const SyntheticSpec& spec);
inline constexpr const char* kSyntheticHeader =
    "operator,sensor_id,time_s,temp_v,gyro_v,supply_v,encoder_deg,chamber_c";
// good.csv of `dir`, the synthetic run (SyntheticSpec{}), and `bad_file` of `dir`, the same text
// with each line of `inserted` after the data line of its 0-based index (the header is line 1, so
// a line inserted after index i is line i + 3, plus one per line inserted before it).
void WriteGoodAndBad(const Scratch& dir, const std::string& bad_file,
                     const std::map<size_t, std::string>& inserted);

csv::CsvFile ReadCsvFile(const std::string& path);
std::string Slurp(const std::string& path);
void WriteText(const std::string& path, const std::string& text);

// Waits (bounded) for a STATUS of each child on `url`: they have subscribed by then. Heartbeats
// come once a second, so this can take ~1 s: give recorders an --idle-exit-s well above that.
bool WaitForStatus(const std::string& url, const std::vector<const launch::ChildProcess*>& children,
                   std::chrono::milliseconds timeout = std::chrono::seconds(10));
inline bool WaitForStatus(const std::string& url, const launch::ChildProcess& child) {
    return WaitForStatus(url, std::vector<const launch::ChildProcess*>{&child});
}

// gyrocal-csv-record writing `out` (a file of `dir`) from `url`, its stderr in `err` (of `dir`),
// leaving after 3 s without samples; `extra` options follow.
launch::ChildProcess StartCsvRecord(const Scratch& dir, const std::string& url,
                                    const std::string& out = "out.csv",
                                    const std::string& err = "rec.err",
                                    const std::vector<std::string>& extra = {});
// gyrocal-csv-source publishing `csv` (a file of `dir`) on `url`, its stderr in source.err of
// `dir`; `extra` options follow.
launch::ChildProcess StartCsvSource(const Scratch& dir, const std::string& url,
                                    const std::string& csv,
                                    const std::vector<std::string>& extra = {});

// Waits for exit; a child still running after `timeout` is stopped and reported as failed.
launch::ExitStatus WaitExit(launch::ChildProcess& child, std::chrono::milliseconds timeout);

// Expects `recorded` to hold exactly the samples of `original` (per sensor, in order): same
// count, time_s to the microsecond, and every value bit-identical; temp_c must equal the
// default transfer function of temp_v (the source computed it; the CSV had no temp_c).
// `sensors` restricts the comparison (empty = all).
void ExpectSameSamples(const csv::CsvFile& original, const csv::CsvFile& recorded,
                       const std::vector<std::string>& sensors = {});

}  // namespace gyrocal::test
