#include "store/db/utc_text.hpp"

#include <chrono>
#include <ctime>

namespace gyrocal::db {

int64_t WallUtimeNow() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

std::string UtcText(std::optional<int64_t> utime) {
    if (!utime) return "-";
    const std::time_t t = static_cast<std::time_t>(*utime / 1000000);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
    return buf;
}

}  // namespace gyrocal::db
