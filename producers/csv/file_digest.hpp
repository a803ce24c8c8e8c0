#pragma once
// The SHA-256 of a file, so that a run records exactly which measured data it was made from
// (gyrocal calibrate --source csv|log writes it into the run's configuration as input_sha256;
// `sha256sum FILE` gives the same hex digits).
#include <stdexcept>
#include <string>

namespace gyrocal::csv {

// 64 lower-case hex digits. Throws std::runtime_error naming the file when it cannot be read.
std::string Sha256HexOfFile(const std::string& path);

}  // namespace gyrocal::csv
