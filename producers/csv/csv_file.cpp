#include "producers/csv/csv_file.hpp"

#include "producers/csv/fields.hpp"

namespace gyrocal::csv {

CsvReader::CsvReader(std::istream& in, std::string file, sensor::TempTransfer transfer,
                     OnError policy, long max_rows)
    : in_(in), file_(std::move(file)), transfer_(transfer), policy_(policy), max_rows_(max_rows) {}

std::optional<CsvRow> CsvReader::Next() {
    while (std::getline(in_, line_)) {
        ++line_no_;
        if (IsBlankOrComment(line_)) continue;
        if (!parser_) {
            Header h = ParseHeader(line_, file_, line_no_);
            unknown_ = h.unknown;
            parser_.emplace(std::move(h), file_, transfer_);
            continue;
        }
        if (max_rows_ >= 0 && data_rows_ >= max_rows_) break;
        ++data_rows_;
        try {
            return parser_->Parse(line_, line_no_);
        } catch (const CsvError& e) {
            if (policy_ == OnError::kStop) throw;
            if (errors_.size() < kKeptErrors) errors_.push_back(e.what());
            ++skipped_;
        }
    }
    if (!parser_) {
        throw CsvError(file_, line_no_ + 1, "time_s",
                       std::string("no header row: the file is empty; the first line must name "
                                   "the columns, required ") +
                           kRequiredColumns);
    }
    return std::nullopt;
}

CsvFile ReadCsv(std::istream& in, const std::string& file, const sensor::TempTransfer& transfer,
                OnError policy, long max_rows) {
    CsvFile out;
    CsvReader reader(in, file, transfer, policy, max_rows);
    while (std::optional<CsvRow> row = reader.Next()) out.rows.push_back(std::move(*row));
    out.unknown = reader.unknown();
    out.errors = reader.errors();
    out.skipped = reader.skipped();
    return out;
}

}  // namespace gyrocal::csv
