#pragma once
// Percentiles of measured latencies by the nearest-rank definition (the smallest value with at
// least p % of the values at or below it): always one of the measured values, never
// interpolated, so "p99 = 412 us" means 1 % of the samples took longer than 412 us.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

namespace gyrocal::bench {

// pct in (0, 100]; `sorted` ascending and not empty.
inline double NearestRank(const std::vector<double>& sorted, double pct) {
    const double n = static_cast<double>(sorted.size());
    const auto rank = static_cast<size_t>(std::max(1.0, std::ceil(pct / 100.0 * n - 1e-9)));
    return sorted[std::min(rank, sorted.size()) - 1];
}

struct LatencySummary {
    int64_t count = 0;
    double p50_us = std::numeric_limits<double>::quiet_NaN();  // NaN when count is 0
    double p90_us = std::numeric_limits<double>::quiet_NaN();
    double p99_us = std::numeric_limits<double>::quiet_NaN();
    double p999_us = std::numeric_limits<double>::quiet_NaN();
    double max_us = std::numeric_limits<double>::quiet_NaN();
    double mean_us = std::numeric_limits<double>::quiet_NaN();
};

inline LatencySummary Summarize(std::vector<double> values_us) {
    LatencySummary s;
    s.count = static_cast<int64_t>(values_us.size());
    if (values_us.empty()) return s;
    std::sort(values_us.begin(), values_us.end());
    s.p50_us = NearestRank(values_us, 50.0);
    s.p90_us = NearestRank(values_us, 90.0);
    s.p99_us = NearestRank(values_us, 99.0);
    s.p999_us = NearestRank(values_us, 99.9);
    s.max_us = values_us.back();
    s.mean_us = std::accumulate(values_us.begin(), values_us.end(), 0.0) /
                static_cast<double>(values_us.size());
    return s;
}

}  // namespace gyrocal::bench
