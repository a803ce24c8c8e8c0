#include "csv_file.hpp"

#include <optional>

#include "fields.hpp"

namespace gyrocal::csv {

CsvFile ReadCsv(std::istream& in, const std::string& file, const sensor::TempTransfer& transfer,
                OnError policy, long max_rows) {
    CsvFile out;
    std::optional<RowParser> parser;
    std::string line;
    long line_no = 0;
    long data_rows = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (IsBlankOrComment(line)) continue;
        if (!parser) {
            Header h = ParseHeader(line, file, line_no);
            out.unknown = h.unknown;
            parser.emplace(std::move(h), file, transfer);
            continue;
        }
        if (max_rows >= 0 && data_rows >= max_rows) break;
        ++data_rows;
        try {
            out.rows.push_back(parser->Parse(line, line_no));
        } catch (const CsvError& e) {
            if (policy == OnError::kStop) throw;
            out.errors.push_back(e.what());
            ++out.skipped;
        }
    }
    if (!parser) {
        throw CsvError(file, line_no + 1, "time_s",
                       std::string("no header row: the file is empty; the first line must name "
                                   "the columns, required ") +
                           kRequiredColumns);
    }
    return out;
}

}  // namespace gyrocal::csv
