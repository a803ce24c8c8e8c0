// SeqTracker: per-channel sequence gaps, producer restarts, and extreme seq values.
#include "lcmtypes/bus/seq_tracker.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace gyrocal {
namespace {

TEST(SeqTracker, BackwardsStepIsCountedAndResynchronises) {
    bus::SeqTracker t;
    t.Observe("A", 5);
    t.Observe("A", 6);
    bus::SeqReport r = t.Observe("A", 0);  // producer restarted
    EXPECT_TRUE(r.backwards);
    EXPECT_EQ(t.Observe("A", 1).missing, 0);
    EXPECT_EQ(t.Observe("A", 4).missing, 2);
    EXPECT_EQ(t.total_backwards(), 1);
    EXPECT_EQ(t.total_missing(), 2);
}

// Found by the fuzz harness recorder_map (UBSan): a hostile seq near INT64_MIN or INT64_MAX
// overflowed the gap arithmetic. Gaps are exact where they fit, saturate where they do not.
TEST(SeqTracker, ExtremeSeqValuesNeitherOverflowNorWrap) {
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
    constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
    bus::SeqTracker t;
    t.Observe("A", kMin);
    EXPECT_EQ(t.Observe("A", kMin + 3).missing, 2);
    EXPECT_EQ(t.Observe("A", kMax).missing, kMax);  // 2^64 - 4 missing: saturated
    EXPECT_EQ(t.total_missing(), kMax);
    EXPECT_TRUE(t.Observe("A", 17).backwards);
    EXPECT_EQ(t.Observe("A", kMax).missing, kMax - 18);  // exact: it fits
    EXPECT_EQ(t.total_missing(), kMax);                  // stays saturated, never wraps negative
    EXPECT_TRUE(t.Observe("A", kMax).backwards);  // a repeat of INT64_MAX: no "next" to expect
}

}  // namespace
}  // namespace gyrocal
