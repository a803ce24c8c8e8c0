#pragma once
// A whole CSV file read and validated before anything is published, so a bad file under the
// "stop" policy publishes nothing, and under "skip" every bad row is dropped whole (never half
// a sample) and counted.
#include <istream>
#include <string>
#include <vector>

#include "row_parser.hpp"

namespace gyrocal::csv {

enum class OnError { kStop, kSkip };

struct CsvFile {
    std::vector<CsvRow> rows;          // valid rows in file order
    std::vector<std::string> unknown;  // ignored columns (header order)
    std::vector<std::string> errors;   // skip policy: one message per skipped row
    long skipped = 0;                  // skip policy: rows dropped
};

// Reads `in` (named `file` in messages). Blank lines and '#' comments are ignored.
// Throws CsvError for a bad header, and under kStop for the first bad row.
// max_rows >= 0 stops after that many data rows (a check of the file's head: the header and the
// first rows; the rest is not read); < 0 reads the whole file.
CsvFile ReadCsv(std::istream& in, const std::string& file, const sensor::TempTransfer& transfer,
                OnError policy, long max_rows = -1);

}  // namespace gyrocal::csv
