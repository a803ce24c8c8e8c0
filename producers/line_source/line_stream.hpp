#pragma once
// LineStream: the text protocol of a live line stream, apart from its transport and the bus.
// The first line that is not blank or a '#' comment is the header; after it each line is a row,
// a repeat of the header (a DAQ that restarted: ignored), a blank or comment line (ignored), or a
// bad line (skipped whole, with the reason naming STREAM:LINE and the column). A first line that
// is not a valid header is fatal: nothing after it can be read. Line numbers count every line.
// Pure: no LCM, no clock, no file access (gyrocal-line-source and the fuzz harness share it).
#include <optional>
#include <string>
#include <vector>

#include "producers/csv/row_parser.hpp"
#include "producers/line_source/line_input.hpp"

namespace gyrocal::line_source {

struct LineOutcome {
    enum class Kind { kIgnored, kHeader, kRow, kBad, kFatal };
    Kind kind = Kind::kIgnored;
    std::optional<csv::CsvRow> row;            // kRow
    std::vector<std::string> unknown_columns;  // kHeader: ignored columns, header order
    std::string message;                       // kBad, kFatal: what is wrong, where
};

class LineStream {
public:
    LineStream(std::string name, sensor::TempTransfer transfer);

    // Never throws for any text.
    LineOutcome Feed(const InputLine& line);

    bool has_header() const { return parser_.has_value(); }
    long line_no() const { return line_no_; }

private:
    std::string name_;
    sensor::TempTransfer transfer_;
    std::optional<csv::RowParser> parser_;
    std::string header_text_;
    long line_no_ = 0;
    bool fatal_ = false;
};

}  // namespace gyrocal::line_source
