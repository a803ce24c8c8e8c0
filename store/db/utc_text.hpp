#pragma once
// Wall-clock times of the database: now, and for people "2026-11-21 05:14:00" (UTC).
#include <cstdint>
#include <optional>
#include <string>

namespace gyrocal::db {

// The UTC date and time of a wall-clock utime [us]; "-" when absent.
std::string UtcText(std::optional<int64_t> utime);

// Now on the wall clock [us since 1970]: what a row written without a time is stamped with.
int64_t WallUtimeNow();

}  // namespace gyrocal::db
