// The test lab itself: two hosts (network namespaces) on the bridge exchange LCM multicast with
// ttl=1 (this file's port 7804), a pulled cable stops it, and what was lost shows as the
// receiver's sequence gaps, exactly.
#include "tests/support/netns/netns_lab.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;
const std::string kUrl = "udpm://239.255.76.67:7804?ttl=1&recv_buf_size=4194304";

TEST(NetnsLab, TwoHostsTalkOverTheBridgeUntilTheCableIsPulled) {
    if (const std::string why = NetnsLab::Unavailable(); !why.empty()) GTEST_SKIP() << why;
    NetnsLab lab("gclab", 2, 201);
    std::atomic<bool> listening{false}, done{false};
    std::mutex mu;
    std::vector<int64_t> got;
    int64_t receiver_gaps = -1;
    std::thread rx = lab.OnHost(2, [&] {
        bus::Bus bus(bus::BusOptions{kUrl});
        bus.Subscribe<gyro_sample_t>(channels::Gyro("N1"),
                                     [&](const gyro_sample_t& m, const std::string&) {
                                         std::lock_guard<std::mutex> l(mu);
                                         got.push_back(m.seq);
                                     });
        listening = true;
        while (!done) bus.Handle(20ms);
        for (int i = 0; i < 10; ++i) bus.Handle(20ms);
        receiver_gaps = bus.counters().seq_gaps;
    });
    EXPECT_TRUE(testing::WaitUntil([&] { return listening.load(); }, 10s))
        << "the receiver never subscribed";
    int64_t sent = 0, sent_before_cut = 0, sent_after_restore = 0;
    std::thread tx = lab.OnHost(1, [&] {
        bus::Bus bus(bus::BusOptions{kUrl});
        gyro_sample_t m{};
        m.sensor_id = "N1";
        // 600 messages at about 200/s; the cable is out for messages 200 to 399. Counted in
        // messages, not seconds: on a loaded machine pulling the cable (an `ip` process) can take
        // most of a second, which would leave a time-defined cut with few messages in it.
        constexpr int64_t kCutAt = 200, kRestoreAt = 400, kTotal = 600;
        while (sent < kTotal) {
            if (sent == kCutAt) {
                sent_before_cut = sent;
                lab.SetLink(1, false);
            }
            if (sent == kRestoreAt) {
                lab.SetLink(1, true);
                sent_after_restore = sent;
            }
            m.seq = sent++;
            bus.Publish(channels::Gyro("N1"), m);
            // Time itself: the sender's rate (about 200/s, a sensor's), not a wait on anything.
            std::this_thread::sleep_for(5ms);
        }
    });
    tx.join();
    // The last message has crossed (bounded: if it was lost the checks below say so).
    testing::WaitUntil(
        [&] {
            std::lock_guard<std::mutex> l(mu);
            return !got.empty() && got.back() == sent - 1;
        },
        5s);
    done = true;
    rx.join();
    std::lock_guard<std::mutex> l(mu);
    ASSERT_FALSE(got.empty()) << "nothing crossed the bridge";
    // THEN everything sent before the cut arrived, nothing sent during it, and traffic resumed
    // (the first packets after re-plugging may still be lost while the port comes up: bounded).
    EXPECT_EQ(got.front(), 0);
    for (int64_t s = 0; s < sent_before_cut; ++s) EXPECT_EQ(got[static_cast<size_t>(s)], s);
    for (int64_t s : got)
        EXPECT_FALSE(s >= sent_before_cut + 2 && s < sent_after_restore) << "seq " << s;
    EXPECT_EQ(got.back(), sent - 1);
    // The receiver counted exactly what it did not get (no reordering on one cable).
    EXPECT_EQ(receiver_gaps, sent - static_cast<int64_t>(got.size()));
    // Every message sent with the cable out is lost, but for the 2 the check above lets through.
    EXPECT_GE(receiver_gaps, sent_after_restore - sent_before_cut - 2) << "200 messages were cut";
}

}  // namespace
}  // namespace gyrocal::testing
