// WriterWatch: the recorder's STATUS state and log lines through a storage fault, from a
// sequence of AsyncWriter stats (GIVEN a time line, THEN what is said when).
#include "store/recorder/writer_watch.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace gyrocal::recorder {
namespace {

using namespace std::chrono_literals;
using Clock = WriterWatch::Clock;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

double Extra(const WatchReport& r, const std::string& name) {
    for (const auto& [n, v] : r.extras) {
        if (n == name) return v;
    }
    ADD_FAILURE() << "no extra " << name;
    return -1;
}

TEST(WriterWatch, SaysWhenAFaultBeginsWhileItLastsAndWhenItEnds) {
    WriterWatch w(1000, 10s);
    const Clock::time_point t0{};
    db::AsyncWriterStats s;
    s.written = 50;

    WatchReport r = w.Update(s, t0);
    EXPECT_EQ(r.state, "recording");
    EXPECT_TRUE(r.log.empty());

    // WHEN a write fails with a storage fault
    s.blocked = true;
    s.blocked_since = t0 + 1s;
    s.blocked_reason = "disk full";
    s.blocked_error = "database 'x.db': database or disk is full";
    s.held_rows = 300;
    r = w.Update(s, t0 + 1200ms);
    EXPECT_EQ(r.state, "db_blocked:disk_full");
    EXPECT_THAT(r.log, ElementsAre(AllOf(HasSubstr("database writes fail (disk full): database "
                                                   "'x.db': database or disk is full"),
                                         HasSubstr("300 rows in memory (bound 1000 rows"))));
    EXPECT_DOUBLE_EQ(Extra(r, "held_rows"), 300);
    EXPECT_DOUBLE_EQ(Extra(r, "held_bound_rows"), 1000);
    EXPECT_NEAR(Extra(r, "db_blocked_s"), 0.2, 1e-9);

    // THEN silence until the repeat period, then one reminder with the drops since it began
    s.held_rows = 1000;
    s.dropped = 40;
    EXPECT_TRUE(w.Update(s, t0 + 5s).log.empty());
    r = w.Update(s, t0 + 11200ms);
    EXPECT_THAT(r.log, ElementsAre(AllOf(
                           HasSubstr("still failing (disk full) after 10.2 s: 1000 rows in memory"),
                           HasSubstr("40 dropped at the bound"))));

    // WHEN a write succeeds again
    s.blocked = false;
    s.written = 50 + 1000;
    s.held_rows = 0;
    r = w.Update(s, t0 + 13s);
    EXPECT_EQ(r.state, "recording");
    EXPECT_THAT(r.log, ElementsAre(HasSubstr("writable again after 12.0 s: 1000 rows written "
                                             "since the fault began, 40 dropped at the bound")));
    EXPECT_TRUE(w.Update(s, t0 + 30s).log.empty());
}

}  // namespace
}  // namespace gyrocal::recorder
