#pragma once
// Splitting a CSV line and reading one numeric field. The format is the plain one that DAQ
// software and spreadsheets write: comma separated, no embedded commas; surrounding blanks and
// one pair of surrounding double quotes are removed; a trailing CR (Windows files, serial
// lines) is ignored.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::csv {

std::vector<std::string> SplitFields(std::string_view line);

// True for a line that carries nothing (empty, blanks only, or a '#' comment).
bool IsBlankOrComment(std::string_view line);

enum class NumberStatus { kOk, kEmpty, kNotANumber, kNotFinite };
struct Number {
    NumberStatus status = NumberStatus::kEmpty;
    double value = 0.0;
};
// Parses the whole field as a decimal number (an optional leading '+' is accepted).
Number ParseNumber(std::string_view field);

}  // namespace gyrocal::csv
