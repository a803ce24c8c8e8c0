#pragma once
// The header row of a measured-data CSV or line stream: which field holds which column.
// Columns may come in any order; unknown columns are kept by name so the caller can warn once.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocal::csv {

// A malformed file or line: what() is "FILE:LINE: column NAME: what is wrong; what is valid"
// ("FILE:LINE: what ..." when no one column is at fault, column empty).
class CsvError : public std::runtime_error {
public:
    CsvError(const std::string& file, long line, const std::string& column,
             const std::string& what);
    long line() const { return line_; }
    const std::string& column() const { return column_; }

private:
    long line_;
    std::string column_;
};

enum class Column {
    kTimeS,
    kSensorId,
    kGyroV,
    kTempV,
    kTempC,
    kSupplyV,
    kEncoderDeg,
    kChamberC,
    kTimeSincePowerS
};
inline constexpr int kNumColumns = 9;
const char* ColumnName(Column c);
inline constexpr const char* kRequiredColumns = "time_s, sensor_id, gyro_v, temp_v";
inline constexpr const char* kOptionalColumns =
    "temp_c, supply_v, encoder_deg, chamber_c, time_since_power_s";

struct Header {
    int num_fields = 0;                     // fields in the header row
    std::optional<int> index[kNumColumns];  // field index of each known column
    std::vector<std::string> unknown;       // names of ignored columns, in header order
    std::optional<int> Index(Column c) const { return index[static_cast<int>(c)]; }
};

// Throws CsvError (line `line_no`) for a missing required column, an empty or duplicate name.
Header ParseHeader(const std::string& line, const std::string& file, long line_no);

}  // namespace gyrocal::csv
