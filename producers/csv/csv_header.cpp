#include "producers/csv/csv_header.hpp"

#include "lcmtypes/text/names.hpp"
#include "producers/csv/fields.hpp"

namespace gyrocal::csv {

CsvError::CsvError(const std::string& file, long line, const std::string& column,
                   const std::string& what)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " +
                         (column.empty() ? "" : "column " + column + ": ") + what),
      line_(line),
      column_(column) {}

namespace {

// Declaration order of Column, so that a column's row is also its index.
constexpr text::NameTable<Column, kNumColumns> kColumnNames{
    {{Column::kTimeS, "time_s"},
     {Column::kSensorId, "sensor_id"},
     {Column::kGyroV, "gyro_v"},
     {Column::kTempV, "temp_v"},
     {Column::kTempC, "temp_c"},
     {Column::kSupplyV, "supply_v"},
     {Column::kEncoderDeg, "encoder_deg"},
     {Column::kChamberC, "chamber_c"},
     {Column::kTimeSincePowerS, "time_since_power_s"}}};

}  // namespace

const char* ColumnName(Column c) { return text::NameOf(kColumnNames, c); }

Header ParseHeader(const std::string& line, const std::string& file, long line_no) {
    Header h;
    const std::vector<std::string> names = SplitFields(line);
    h.num_fields = static_cast<int>(names.size());
    for (int i = 0; i < h.num_fields; ++i) {
        const std::string& name = names[i];
        if (name.empty()) {
            throw CsvError(file, line_no, "#" + std::to_string(i + 1),
                           "empty column name in the header; every header field needs a name");
        }
        const std::optional<Column> column = text::ValueOf(kColumnNames, name);
        if (!column) {
            h.unknown.push_back(name);
            continue;
        }
        std::optional<int>& index = h.index[static_cast<int>(*column)];
        if (index) {
            throw CsvError(file, line_no, name,
                           "appears twice in the header; each column may appear once");
        }
        index = i;
    }
    for (Column c : {Column::kTimeS, Column::kSensorId, Column::kGyroV, Column::kTempV}) {
        if (!h.Index(c)) {
            throw CsvError(file, line_no, ColumnName(c),
                           std::string("missing from the header; required columns are ") +
                               kRequiredColumns + " (optional: " + kOptionalColumns + ")");
        }
    }
    return h;
}

}  // namespace gyrocal::csv
