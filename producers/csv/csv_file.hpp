#pragma once
// A whole CSV file read and validated before anything is published, so a bad file under the
// "stop" policy publishes nothing, and under "skip" every bad row is dropped whole (never half
// a sample) and counted.
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "producers/csv/row_parser.hpp"

namespace gyrocal::csv {

enum class OnError { kStop, kSkip };

struct CsvFile {
    std::vector<CsvRow> rows;          // valid rows in file order
    std::vector<std::string> unknown;  // ignored columns (header order)
    std::vector<std::string> errors;   // skip policy: one message per skipped row (the first 1000)
    long skipped = 0;                  // skip policy: rows dropped
};

// A CSV file row by row, in bounded memory (a day of 16 units is 138M rows: a source checks the
// whole file in a first pass with one reader, then publishes it in a second pass with another).
// Blank lines and '#' comments are ignored.
class CsvReader {
public:
    // max_rows >= 0 stops after that many data rows (a check of the file's head: the header and
    // the first rows; the rest is not read); < 0 reads the whole file.
    CsvReader(std::istream& in, std::string file, sensor::TempTransfer transfer, OnError policy,
              long max_rows = -1);
    // The next valid row; nullopt at the end of the file. Throws CsvError for a bad header (or a
    // file without one), and under kStop for the first bad row; under kSkip a bad row is counted
    // (skipped()) and its message kept among the first `kKeptErrors`.
    std::optional<CsvRow> Next();
    const std::vector<std::string>& unknown() const { return unknown_; }
    const std::vector<std::string>& errors() const { return errors_; }
    long skipped() const { return skipped_; }
    static constexpr size_t kKeptErrors = 1000;

private:
    std::istream& in_;
    std::string file_;
    sensor::TempTransfer transfer_;
    OnError policy_;
    std::optional<RowParser> parser_;
    std::vector<std::string> unknown_;
    std::vector<std::string> errors_;
    long skipped_ = 0;
    long max_rows_ = -1;
    long data_rows_ = 0;
    long line_no_ = 0;
    std::string line_;
};

// Reads `in` (named `file` in messages) whole, or its first max_rows data rows (max_rows >= 0).
// Throws CsvError for a bad header, and under kStop for the first bad row.
CsvFile ReadCsv(std::istream& in, const std::string& file, const sensor::TempTransfer& transfer,
                OnError policy, long max_rows = -1);

}  // namespace gyrocal::csv
