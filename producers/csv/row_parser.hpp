#pragma once
// One data row -> a validated CsvRow, or a CsvError naming file, line and column. The parser
// keeps the last time_s of each sensor so that time must strictly increase per sensor (rows of
// several sensors may interleave); a row that fails leaves that state untouched, so skipping a
// bad row never poisons the rows after it.
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "producers/csv/csv_header.hpp"
#include "producers/sensor/temp_transfer.hpp"

namespace gyrocal::csv {

// [s] Covers Unix-epoch seconds (until 2096) while a double still resolves the microsecond
// (ulp at 4e9 s is 0.5 us) and start_utime + time_s stays far from int64 overflow.
inline constexpr double kMaxAbsTimeS = 4e9;
// [us] time_s on the microsecond grid of utime.
inline long long TimeUs(double time_s) { return std::llround(time_s * 1e6); }

struct CsvRow {
    long line = 0;        // source line number (1-based)
    double time_s = 0.0;  // [s] data time
    std::string sensor_id;
    double gyro_v = 0.0;                // [V]
    double temp_v = 0.0;                // [V]
    double temp_c = 0.0;                // [degC] from the file, else via the transfer function
    std::optional<double> supply_v;     // [V]
    std::optional<double> encoder_deg;  // [deg] cumulative turntable angle
    std::optional<double> chamber_c;    // [degC] chamber air
    std::optional<double> time_since_power_s;  // [s] since the unit was powered, >= 0
};

class RowParser {
public:
    RowParser(Header header, std::string file, sensor::TempTransfer transfer);

    // Throws CsvError when the line is malformed; the per-sensor time state is then unchanged.
    CsvRow Parse(const std::string& line, long line_no);

    const Header& header() const { return header_; }
    const std::string& file() const { return file_; }

private:
    struct Last {
        double time_s;
        long line;
        std::string text;  // time_s as written, for messages
    };
    Header header_;
    std::string file_;
    sensor::TempTransfer transfer_;
    std::map<std::string, Last> last_;
};

}  // namespace gyrocal::csv
