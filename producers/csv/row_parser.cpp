#include "producers/csv/row_parser.hpp"

#include <cmath>
#include <vector>

#include "lcmtypes/channels/channels.hpp"
#include "producers/csv/fields.hpp"

namespace gyrocal::csv {

RowParser::RowParser(Header header, std::string file, sensor::TempTransfer transfer)
    : header_(std::move(header)), file_(std::move(file)), transfer_(transfer) {}

namespace {

// Throws unless the line has exactly one field per header column. A short line is refused as a
// whole, naming the first known column it lacks (or the first missing field when only unknown
// columns are missing).
void CheckFieldCount(const Header& header, const std::string& file, long line_no, int n) {
    if (n > header.num_fields) {
        throw CsvError(file, line_no, "#" + std::to_string(header.num_fields + 1),
                       "line has " + std::to_string(n) + " fields, the header has " +
                           std::to_string(header.num_fields) +
                           "; every line needs exactly one field per header column");
    }
    if (n < header.num_fields) {
        int first_missing_known = header.num_fields;
        Column which = Column::kTimeS;
        for (int c = 0; c < kNumColumns; ++c) {
            const auto i = header.index[c];
            if (i && *i >= n && *i < first_missing_known) {
                first_missing_known = *i;
                which = static_cast<Column>(c);
            }
        }
        const std::string col = first_missing_known < header.num_fields
                                    ? std::string(ColumnName(which))
                                    : "#" + std::to_string(n + 1);
        throw CsvError(file, line_no, col,
                       "missing: the line is cut short (" + std::to_string(n) + " of " +
                           std::to_string(header.num_fields) +
                           " fields); every line needs one field per header column");
    }
}

}  // namespace

CsvRow RowParser::Parse(const std::string& line, long line_no) {
    const std::vector<std::string> f = SplitFields(line);
    CheckFieldCount(header_, file_, line_no, static_cast<int>(f.size()));
    // Every header column has its field (checked above).
    auto field = [&](Column c) -> std::optional<std::string> {
        const std::optional<int> i = header_.Index(c);
        if (!i) return std::nullopt;
        return f[*i];
    };
    auto number = [&](Column c, bool required) -> std::optional<double> {
        const std::optional<std::string> s = field(c);
        if (!s) return std::nullopt;
        const Number num = ParseNumber(*s);
        switch (num.status) {
            case NumberStatus::kOk:
                return num.value;
            case NumberStatus::kEmpty:
                if (!required) return std::nullopt;  // an empty optional field = not measured
                throw CsvError(file_, line_no, ColumnName(c),
                               "empty; this column is required: a finite decimal number");
            case NumberStatus::kNotANumber:
                throw CsvError(file_, line_no, ColumnName(c),
                               "'" + *s + "' is not a number; expected a finite decimal number");
            case NumberStatus::kNotFinite:
                throw CsvError(file_, line_no, ColumnName(c),
                               "'" + *s + "' is not finite; expected a finite decimal number");
        }
        return std::nullopt;
    };

    CsvRow row;
    row.line = line_no;
    row.time_s = *number(Column::kTimeS, true);
    row.sensor_id = *field(Column::kSensorId);
    if (!channels::IsValidSensorId(row.sensor_id)) {
        throw CsvError(file_, line_no, "sensor_id",
                       "'" + row.sensor_id +
                           "' is not a valid sensor id; use 1-32 letters, digits, '-' or '_'");
    }
    row.gyro_v = *number(Column::kGyroV, true);
    row.temp_v = *number(Column::kTempV, true);
    const std::optional<double> temp_c = number(Column::kTempC, false);
    row.temp_c = temp_c ? *temp_c : transfer_.TempC(row.temp_v);
    row.supply_v = number(Column::kSupplyV, false);
    row.encoder_deg = number(Column::kEncoderDeg, false);
    row.chamber_c = number(Column::kChamberC, false);
    row.time_since_power_s = number(Column::kTimeSincePowerS, false);
    if (row.time_since_power_s && *row.time_since_power_s < 0.0)
        throw CsvError(file_, line_no, "time_since_power_s",
                       *field(Column::kTimeSincePowerS) +
                           " is negative; valid: seconds since the unit was powered, >= 0");

    const std::string time_text = *field(Column::kTimeS);  // quoted as written
    if (!(std::fabs(row.time_s) <= kMaxAbsTimeS)) {
        throw CsvError(file_, line_no, "time_s",
                       time_text + " is out of range; valid: -4e9 to 4e9 s");
    }
    // Compared at the 1 us resolution of utime, so that every published utime increases too.
    auto it = last_.find(row.sensor_id);
    if (it != last_.end() && !(TimeUs(row.time_s) > TimeUs(it->second.time_s))) {
        throw CsvError(file_, line_no, "time_s",
                       time_text + " is not after " + it->second.text + " of the previous " +
                           row.sensor_id + " row (line " + std::to_string(it->second.line) +
                           "); time_s must strictly increase per sensor (by at least 1 us)");
    }
    last_[row.sensor_id] = Last{row.time_s, line_no, time_text};
    return row;
}

}  // namespace gyrocal::csv
