#pragma once
// The measured-data input of `gyrocal calibrate` checked before any process starts, so that a
// file that cannot be replayed is refused with one line (exit 2) and no run is recorded:
//   --source csv: gyrocal-csv-source itself reads the header and the first kCheckRows rows with
//                 the run's own --source-arg options (the same parser and conversion as the run:
//                 what the options say about the file is checked against the file);
//   --source log: the file starts with LCM's log sync word;
//   --source lines: a stream, nothing to read ahead.
// A bad row further down is found by the source during the run, which then ends with the source's
// own error line printed and stored (child_errors.hpp).
#include <string>

#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::supervisor {

inline constexpr long kCheckRows = 100;  // rows read ahead: every column's format, a few sensors

// "" when the input can be used, else one line: "FILE:LINE: column NAME: what; what is valid".
std::string MeasuredInputProblem(const CalibrateOptions& o);

// The LCM log check alone (first bytes of `path`): "" or the problem.
std::string LcmLogProblem(const std::string& path);

}  // namespace gyrocal::supervisor
