#pragma once
// Offline compensation: a stored coefficient set, or its JSON export, applied to measured data
// read from a CSV (producers/csv), with the live compensator's library, so that a model can be
// judged on data it never saw and the numbers equal what gyrocal-compensator would have published
// for the same samples. The command (`gyrocal compensate`) is built in tools/cli.
//
// Same path as live: each CSV row becomes the gyro_sample_t a CSV source would publish
// (csv::MessageBuilder: seq per sensor from 0; utime = start_utime + time_s on the microsecond
// grid, csv::StreamUtime), which is handed to SensorCompensator exactly as
// gyrocal-compensator hands it a GYRO_<id> message ({utime, seq, gyro_v, temp_c, supply_v}).
// One compensator per sensor, its set applied before the sensor's first sample (so the angle
// starts at 0 on the first sample). A sample the live compensator would not publish (e.g. a dTdt
// model during the first half-window of the dT/dt estimator) gets no output row; it is counted
// and the first one is named (line and why).
// Pure: no LCM transport, no SQLite, no clock, no file access.
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "processors/compensator/compensate.hpp"
#include "processors/model/convert.hpp"
#include "producers/csv/row_messages.hpp"
#include "producers/csv/row_parser.hpp"

namespace gyrocal::compensator {

// Bad input (names the file, line or JSON field and what is valid).
class OfflineError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct OfflineOptions {
    CompensatorOptions core = CompensatorOptions::Defaults();
    int64_t start_utime = csv::kDefaultStartUtime;  // [us] utime of time_s = 0
    static OfflineOptions Defaults() { return {}; }
};

struct OfflineRate {
    long line = 0;        // CSV line of the sample
    double time_s = 0.0;  // [s] as in the CSV
    std::string sensor_id;
    double rate_dps = 0.0;
    double angle_deg = 0.0;
    double temp_c = 0.0;  // [degC] the temperature the models were evaluated with
    int range_flag = 0;   // rate_t.range_flag: 0 in range, 1 clipped, 2 extrapolated
    int64_t coeff_set_id = -1;
};

struct OfflineResult {
    std::vector<OfflineRate> rates;  // in file order
    long skipped = 0;                // samples the live compensator would not publish either
    std::string first_skip;          // "line N (sensor S): why"
};

// sets: by sensor id. Throws OfflineError when a row's sensor has no set (naming the line, the
// sensor and the sensors the sets cover) or a set is refused by the compensator (naming it).
// csv_file / coeff_origin only name things in messages.
OfflineResult CompensateRows(const std::vector<csv::CsvRow>& rows,
                             const std::map<std::string, model::CoeffSet>& sets,
                             const std::string& csv_file, const std::string& coeff_origin,
                             const OfflineOptions& options = OfflineOptions::Defaults());

// The coefficient sets of a JSON text: the export format of `gyrocal export --format json`
// ({"coeff_sets": [ {sensor_id, run_id, coeff_set_id, source, utime, offset{...},
// sensitivity{...}, ...}, ... ]}) or one such set object. Throws OfflineError naming the file and
// the JSON field (malformed JSON: with the parser's byte position); two sets for one sensor are
// refused (which one would be meant?).
std::map<std::string, model::CoeffSet> CoeffSetsFromJson(const std::string& text,
                                                         const std::string& file);

// "time_s,sensor_id,rate_dps,angle_deg,temp_c,range_flag" and one line per rate; numbers with 17
// significant digits (they read back to the same double).
std::string FormatRatesCsv(const std::vector<OfflineRate>& rates);

}  // namespace gyrocal::compensator
