#include "csv_header.hpp"

#include "fields.hpp"

namespace gyrocal::csv {

CsvError::CsvError(const std::string& file, long line, const std::string& column,
                   const std::string& what)
    : std::runtime_error(file + ":" + std::to_string(line) + ": column " + column + ": " + what),
      line_(line),
      column_(column) {}

const char* ColumnName(Column c) {
    switch (c) {
        case Column::kTimeS:
            return "time_s";
        case Column::kSensorId:
            return "sensor_id";
        case Column::kGyroV:
            return "gyro_v";
        case Column::kTempV:
            return "temp_v";
        case Column::kTempC:
            return "temp_c";
        case Column::kSupplyV:
            return "supply_v";
        case Column::kEncoderDeg:
            return "encoder_deg";
        case Column::kChamberC:
            return "chamber_c";
        case Column::kTimeSincePowerS:
            return "time_since_power_s";
    }
    return "?";
}

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
        bool known = false;
        for (int c = 0; c < kNumColumns; ++c) {
            if (name != ColumnName(static_cast<Column>(c))) continue;
            if (h.index[c]) {
                throw CsvError(file, line_no, name,
                               "appears twice in the header; each column may appear once");
            }
            h.index[c] = i;
            known = true;
        }
        if (!known) h.unknown.push_back(name);
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
