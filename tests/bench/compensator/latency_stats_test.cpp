// Nearest-rank percentiles of the latency benchmark against values worked out by hand.
#include "tests/bench/compensator/latency_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gyrocal::bench {
namespace {

TEST(LatencyStats, NearestRankOfOneToOneThousand) {
    // GIVEN 1..1000 in a shuffled order
    std::vector<double> v;
    for (int i = 1000; i >= 1; --i) v.push_back(i);
    // THEN p is the value at rank ceil(p/100 * 1000): exact, no interpolation
    const LatencySummary s = Summarize(v);
    EXPECT_EQ(s.count, 1000);
    EXPECT_EQ(s.p50_us, 500.0);
    EXPECT_EQ(s.p90_us, 900.0);
    EXPECT_EQ(s.p99_us, 990.0);
    EXPECT_EQ(s.p999_us, 999.0);
    EXPECT_EQ(s.max_us, 1000.0);
    EXPECT_DOUBLE_EQ(s.mean_us, 500.5);
}

TEST(LatencyStats, FewValuesGiveTheLargestForHighPercentiles) {
    // 3 values: rank ceil(0.5 * 3) = 2 for p50; ceil(0.99 * 3) = 3 for p99.
    const LatencySummary s = Summarize({30.0, 10.0, 20.0});
    EXPECT_EQ(s.p50_us, 20.0);
    EXPECT_EQ(s.p99_us, 30.0);
    EXPECT_EQ(Summarize({7.0}).p50_us, 7.0);
}

TEST(LatencyStats, NoValuesAreNotANumber) {
    const LatencySummary s = Summarize({});
    EXPECT_EQ(s.count, 0);
    EXPECT_TRUE(std::isnan(s.p50_us));
    EXPECT_TRUE(std::isnan(s.max_us));
}

}  // namespace
}  // namespace gyrocal::bench
