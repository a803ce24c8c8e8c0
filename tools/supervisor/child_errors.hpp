#pragma once
// What a child process said when it failed, for the line that ends a run: every gyrocal process
// writes its fatal messages in one shape ("<process>: error: <where>: <what>; <valid>",
// lcmtypes/process/process_main.hpp), so the launcher can surface them as they are instead of
// pointing at a log file.
#include <string>
#include <vector>

namespace gyrocal::supervisor {

// The last `max_lines` error lines of `process` in `log_text`, without the "<process>: error: "
// prefix, oldest first. When the log holds none (a crash, a signal), its last non-empty line as
// "last line of its log: ..."; nothing when the log is empty.
std::vector<std::string> ErrorLinesOf(const std::string& log_text, const std::string& process,
                                      size_t max_lines = 3);

// "what; it said: " and the lines joined by " | " (what alone when there are none): the
// reason stored with the run and printed under the abort line.
std::string WithCause(const std::string& what, const std::vector<std::string>& lines);

}  // namespace gyrocal::supervisor
