// FlowWindow (lcmtypes/flow/flow_window.hpp): the credit a source gets from its consumers'
// answers, exactly, on a clock the test drives. Byte counts are chosen so that every expected
// credit is a sum the test states: each datagram costs its payload plus kDatagramOverheadBytes.
#include "lcmtypes/flow/flow_window.hpp"

#include <gtest/gtest.h>

namespace gyrocal::flow {
namespace {

using namespace std::chrono_literals;
constexpr int64_t kDatagram = 1000 + kDatagramOverheadBytes;  // one 1000-byte datagram, charged

WindowOptions Options() {
    WindowOptions o;
    o.window_bytes = 10 * kDatagram;
    o.mark_every_bytes = 2 * kDatagram;
    o.consumer_timeout_s = 5;
    o.remark_s = 0.05;
    return o;
}

const ConsumerId kA{"h", 1}, kB{"h", 2};

// GIVEN A and B paced on (both answered a first mark), then 10 datagrams out and a second mark
// after them, answered by nobody yet: that mark.
Mark TenOwedByBoth(FlowWindow& w, Time t0) {
    const Mark m1 = w.IssueMark(t0);
    w.OnAck(kA, "a", m1.mark_seq, t0);
    w.OnAck(kB, "b", m1.mark_seq, t0);
    w.OnPublished(10, 10000);
    return w.IssueMark(t0);
}

TEST(FlowWindow, NobodyToPaceOnIsNoCredit) {
    FlowWindow w(Options());
    EXPECT_FALSE(w.Credit(Time{}).has_value());
    EXPECT_EQ(w.Slowest(), "");
}

TEST(FlowWindow, CreditIsTheWindowLessWhatTheSlowestConsumerHasNotAnswered) {
    FlowWindow w(Options());
    const Time t0{};
    // GIVEN a first mark answered by two consumers
    const Mark m1 = w.IssueMark(t0);
    w.OnAck(kA, "a", m1.mark_seq, t0);
    w.OnAck(kB, "b", m1.mark_seq, t0);
    ASSERT_EQ(w.Credit(t0), 10 * kDatagram);
    // WHEN 4 datagrams go out, a mark after them, and only A answers it
    w.OnPublished(4, 4000);
    const Mark m2 = w.IssueMark(t0);
    EXPECT_EQ(m2.sent_bytes, 4 * kDatagram);
    w.OnAck(kA, "a", m2.mark_seq, t0);
    // THEN B, four datagrams behind, sets the credit; once B answers, the whole window is free
    EXPECT_EQ(w.Credit(t0), 6 * kDatagram);
    EXPECT_NE(w.Slowest().find("b (pid 2 on h), behind"), std::string::npos) << w.Slowest();
    w.OnAck(kB, "b", m2.mark_seq, t0);
    EXPECT_EQ(w.Credit(t0), 10 * kDatagram);
    EXPECT_TRUE(w.AllAcked(m2.mark_seq));
    // An answer to a mark never issued (another run of the same pid) changes nothing.
    w.OnAck(kB, "b", 99, t0);
    EXPECT_EQ(w.Credit(t0), 10 * kDatagram);
}

TEST(FlowWindow, AMarkIsDueEveryMarkEveryBytesAndAgainWhileWaiting) {
    FlowWindow w(Options());
    const Time t0{};
    EXPECT_TRUE(w.MarkDue(t0));  // none yet
    const Mark m1 = w.IssueMark(t0);
    w.OnAck(kA, "a", m1.mark_seq, t0);
    w.OnPublished(1, 1000);
    EXPECT_FALSE(w.MarkDue(t0));
    w.OnPublished(1, 1000);
    EXPECT_TRUE(w.MarkDue(t0));  // 2 datagrams = mark_every_bytes
    w.IssueMark(t0);
    // Waiting (no credit): a fresh mark every remark_s, so a late consumer can answer.
    w.OnPublished(8, 8000);
    ASSERT_LE(*w.Credit(t0), 0);
    w.IssueMark(t0);
    EXPECT_FALSE(w.MarkDue(t0 + 10ms));
    EXPECT_TRUE(w.MarkDue(t0 + 60ms));
}

TEST(FlowWindow, AProcessHeardOnStatusOwesWhatWasSentAfterItWasHeard) {
    FlowWindow w(Options());
    const Time t0{};
    w.OnPublished(3, 3000);  // before anyone was heard
    w.OnHeartbeat(kA, "a", t0);
    EXPECT_EQ(w.Credit(t0), 10 * kDatagram);
    w.OnPublished(10, 10000);
    EXPECT_EQ(w.Credit(t0), 0);  // it may not have more than the window unanswered
    // Heard again: nothing changes (it is known).
    w.OnHeartbeat(kA, "a", t0 + 1s);
    EXPECT_EQ(w.Credit(t0 + 1s), 0);
}

TEST(FlowWindow, AConsumerThatNeverAnswersIsDroppedAtItsTimeoutAndSaidSo) {
    FlowWindow w(Options());
    const Time t0{};
    w.OnHeartbeat(kA, "gyrocal-old", t0);
    w.OnPublished(10, 10000);
    EXPECT_EQ(w.Credit(t0 + 4s), 0);
    EXPECT_TRUE(w.TakeEvents().empty());
    // At 5 s without progress while owing data: no longer waited for, reported once.
    EXPECT_FALSE(w.Credit(t0 + 5s).has_value());
    const auto events = w.TakeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FlowEvent::Kind::kNotAcking);
    EXPECT_NE(events[0].text.find("gyrocal-old (pid 1 on h) heartbeats on STATUS but has not "
                                  "answered a flow mark for 5 s"),
              std::string::npos)
        << events[0].text;
    EXPECT_EQ(w.dropped_total(), 1);
    EXPECT_TRUE(w.TakeEvents().empty());
}

TEST(FlowWindow, AStuckConsumerIsDroppedAndAdmittedAgainWhenItAnswers) {
    FlowWindow w(Options());
    const Time t0{};
    const Mark m2 = TenOwedByBoth(w, t0);
    // A keeps answering, B is stuck: the source waits for B up to the timeout, then goes on.
    w.OnAck(kA, "a", m2.mark_seq, t0 + 1s);
    EXPECT_EQ(w.Credit(t0 + 4900ms), 0);
    EXPECT_EQ(w.Credit(t0 + 5s), 10 * kDatagram);
    auto events = w.TakeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FlowEvent::Kind::kDropped);
    EXPECT_EQ(events[0].id, kB);
    // B answers again: paced on again, from where it is.
    w.OnAck(kB, "b", m2.mark_seq, t0 + 6s);
    events = w.TakeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FlowEvent::Kind::kReadmitted);
    EXPECT_EQ(w.paced_consumers(), 2u);
}

TEST(FlowWindow, AConsumerThatOwesNothingIsNeverDroppedForBeingQuiet) {
    FlowWindow w(Options());
    const Time t0{};
    const Mark m1 = w.IssueMark(t0);
    w.OnAck(kA, "a", m1.mark_seq, t0);
    EXPECT_EQ(w.Credit(t0 + 1h), 10 * kDatagram);
    EXPECT_TRUE(w.TakeEvents().empty());
}

TEST(FlowWindow, AConsumerThatLeavesIsNoLongerWaitedFor) {
    FlowWindow w(Options());
    const Time t0{};
    const Mark m2 = TenOwedByBoth(w, t0);
    w.OnAck(kA, "a", m2.mark_seq, t0);
    EXPECT_FALSE(w.AllAcked(m2.mark_seq));
    w.OnLeave(kB);
    EXPECT_TRUE(w.AllAcked(m2.mark_seq));
    EXPECT_EQ(w.Credit(t0), 10 * kDatagram);
    w.OnHeartbeat(kB, "b", t0);  // its last heartbeat, after its last answer: still gone
    EXPECT_EQ(w.paced_consumers(), 1u);
    EXPECT_EQ(w.dropped_total(), 0);
}

TEST(FlowWindow, AConsumerWhoseProcessIsGoneIsLeftAtOnceAndSaidSo) {
    FlowWindow w(Options());
    const Time t0{};
    const Mark m2 = TenOwedByBoth(w, t0);
    w.OnAck(kA, "a", m2.mark_seq, t0);
    // Behind: only B owes data.
    ASSERT_EQ(w.Behind(), std::vector<ConsumerId>{kB});
    w.OnGone(kB);
    EXPECT_EQ(w.Credit(t0), 10 * kDatagram);
    const auto events = w.TakeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FlowEvent::Kind::kGone);
    EXPECT_NE(events[0].text.find("b (pid 2 on h) has ended (no such process) owing 20240 B"),
              std::string::npos)
        << events[0].text;
    EXPECT_TRUE(w.Behind().empty());
}

TEST(FlowWindow, OptionsOutOfRangeAreNamed) {
    WindowOptions o = Options();
    EXPECT_EQ(o.Validate(), "");
    o.mark_every_bytes = o.window_bytes + 1;
    EXPECT_NE(o.Validate().find("mark_every_bytes"), std::string::npos);
    o = Options();
    o.consumer_timeout_s = 0;
    EXPECT_NE(o.Validate().find("consumer_timeout_s"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::flow
