// The bus layer in one process over memq:// (LCM's in-process provider): typed delivery,
// decode failures counted instead of lost on stderr, sequence gaps counted, and a handler's
// exception surfaced from Handle() rather than thrown through LCM's C code.
#include "lcmtypes/bus/bus.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <stdexcept>

#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal {
namespace {

using std::chrono::milliseconds;
using testing::EncodeMsg;
using testing::Gyro;

void Drain(bus::Bus& bus) {
    while (bus.Handle(milliseconds(20))) {
    }
}

// Counts into `delivered` what `bus` delivers as a Msg on `channel`.
template <class Msg>
void CountDeliveries(bus::Bus& bus, const std::string& channel, int& delivered) {
    bus.Subscribe<Msg>(channel, [&delivered](const Msg&, const std::string&) { ++delivered; });
}

TEST(Bus, DeliversTypedMessagesToRegexSubscribers) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    std::vector<std::string> seen;
    bus.Subscribe<gyro_sample_t>(channels::AllSensors(channels::kGyroPrefix),
                                 [&](const gyro_sample_t& s, const std::string& ch) {
                                     seen.push_back(ch + ":" + s.sensor_id);
                                 });
    bus.Publish(channels::Gyro("S01"), Gyro("S01", 0));
    bus.Publish(channels::Gyro("S02"), Gyro("S02", 0));
    bus.Publish(std::string(channels::kEncoder), encoder_sample_t{});
    Drain(bus);
    EXPECT_EQ(seen, (std::vector<std::string>{"GYRO_S01:S01", "GYRO_S02:S02"}));
    EXPECT_EQ(bus.counters().received, 2);
    EXPECT_EQ(bus.counters().decode_errors, 0);
}

TEST(Bus, WrongTypeOnChannelIsCountedNotDelivered) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    int delivered = 0;
    CountDeliveries<gyro_sample_t>(bus, "GYRO_X", delivered);
    const encoder_sample_t wrong = testing::Encoder(0);
    bus.Publish("GYRO_X", wrong);
    bus.Publish("GYRO_X", wrong);
    bus.Publish("GYRO_X", Gyro("X", 0));
    Drain(bus);
    EXPECT_EQ(delivered, 1);
    EXPECT_EQ(bus.counters().decode_errors, 2);
    EXPECT_NE(bus.counters().last_decode_error.find("GYRO_X"), std::string::npos);
}

TEST(Bus, SequenceGapsAreCountedPerChannel) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    bus.Subscribe<gyro_sample_t>("GYRO_.*", [](const gyro_sample_t&, const std::string&) {});
    for (int64_t seq : {0, 1, 2, 6, 7}) bus.Publish("GYRO_A", Gyro("A", seq));  // 3..5 lost
    for (int64_t seq : {10, 11, 13}) bus.Publish("GYRO_B", Gyro("B", seq));     // 12 lost
    Drain(bus);
    EXPECT_EQ(bus.counters().seq_gaps, 4);
    EXPECT_EQ(bus.seq().missing_of("GYRO_A"), 3);
    EXPECT_EQ(bus.seq().missing_of("GYRO_B"), 1);
}

TEST(Bus, HandlerExceptionIsRethrownFromHandle) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    bus.Subscribe<gyro_sample_t>("GYRO_A", [](const gyro_sample_t&, const std::string&) {
        throw std::runtime_error("handler failed");
    });
    bus.Publish("GYRO_A", Gyro("A", 0));
    EXPECT_THROW(Drain(bus), std::runtime_error);
}

// Issue 27: a handler that throws must not keep the message from the channel's later
// subscribers; each failure is counted, in all and per channel, with the first one's text.
TEST(Bus, AThrowingHandlerIsCountedAndTheOtherSubscribersStillRun) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    bus.Subscribe<gyro_sample_t>("GYRO_A", [](const gyro_sample_t&, const std::string&) {
        throw std::runtime_error("handler failed");
    });
    int second = 0;
    CountDeliveries<gyro_sample_t>(bus, "GYRO_.*", second);
    bus.Publish("GYRO_A", Gyro("A", 0));
    // The first failure is still rethrown by Handle(), once every subscriber has had the message.
    EXPECT_THROW(Drain(bus), std::runtime_error);
    EXPECT_EQ(second, 1);
    EXPECT_EQ(bus.counters().handler_errors, 1);
    EXPECT_EQ(bus.counters().handler_errors_by_channel.at("GYRO_A"), 1);
    EXPECT_EQ(bus.counters().first_handler_error, "channel GYRO_A: handler failed");
    // Two more on the same channel and one on another (the second handler hears GYRO_B alone):
    // counted per channel; the first text stays.
    bus.Subscribe<gyro_sample_t>("GYRO_B", [](const gyro_sample_t&, const std::string&) {
        throw std::logic_error("other");
    });
    bus.Publish("GYRO_A", Gyro("A", 1));
    bus.Publish("GYRO_A", Gyro("A", 2));
    bus.Publish("GYRO_B", Gyro("B", 0));
    for (int i = 0; i < 3; ++i) EXPECT_ANY_THROW(Drain(bus));
    EXPECT_EQ(second, 4);
    EXPECT_EQ(bus.counters().handler_errors, 4);
    EXPECT_EQ(bus.counters().handler_errors_by_channel.at("GYRO_A"), 3);
    EXPECT_EQ(bus.counters().handler_errors_by_channel.at("GYRO_B"), 1);
    EXPECT_EQ(bus.counters().first_handler_error, "channel GYRO_A: handler failed");
    EXPECT_EQ(bus.counters().received, 8);  // 4 messages x the 2 handlers of each
}

TEST(Bus, UnopenableUrlGivesAnActionableError) {
    try {
        bus::Bus bus(bus::BusOptions{"nosuchprovider://x"});
        FAIL() << "expected BusError";
    } catch (const bus::BusError& e) {
        EXPECT_NE(std::string(e.what()).find("nosuchprovider://x"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("ip route add 224.0.0.0/4 dev lo"), std::string::npos);
    }
}

// A payload with the right fingerprint and a hostile array length (negative num_sensors): the
// generated decode throws inside LCM's dispatch; the bus must count it, not die.
TEST(Bus, HostileArrayLengthIsADecodeErrorNotACrash) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    int delivered = 0;
    CountDeliveries<run_event_t>(bus, "RUN_EVENT", delivered);
    const run_event_t e = testing::RunEvent("r", "start", {"S01"});
    std::vector<uint8_t> buf = EncodeMsg(e);
    // Layout after the 8-byte fingerprint: utime(8), run_id(4+len+1), event(4+len+1), reason(4+1),
    // setpoint_index(4), setpoint_c(8), then num_sensors(int16).
    const size_t at = 8 + 8 + (4 + 2) + (4 + 6) + (4 + 1) + 4 + 8;
    buf[at] = 0x80;  // int16 big-endian: -32768 + ...
    buf[at + 1] = 0x00;
    bus.PublishRaw("RUN_EVENT", buf.data(), static_cast<int>(buf.size()));
    bus.Publish("RUN_EVENT", e);
    Drain(bus);
    EXPECT_EQ(delivered, 1);
    EXPECT_EQ(bus.counters().decode_errors, 1);
}

// Found by the fuzz harnesses (tests/fuzz/README.md): lcm-gen 1.3.1 computed
// (length - 1) of a string length of INT32_MIN, which wrapped into a 2 GB read past the payload:
// a 62-byte RUN_EVENT segfaulted every process. Now a decode error, counted.
TEST(Bus, AStringLengthOfIntMinIsADecodeErrorNotASegfault) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    int delivered = 0;
    CountDeliveries<run_event_t>(bus, "RUN_EVENT", delivered);
    run_event_t e{};
    e.run_id = "r";
    e.event = "start";
    std::vector<uint8_t> buf = EncodeMsg(e);
    const size_t at = 8 + 8;  // after the hash and utime: run_id's int32 length, big-endian
    buf[at] = 0x80;
    buf[at + 1] = buf[at + 2] = buf[at + 3] = 0x00;
    bus.PublishRaw("RUN_EVENT", buf.data(), static_cast<int>(buf.size()));
    Drain(bus);
    EXPECT_EQ(delivered, 0);
    EXPECT_EQ(bus.counters().decode_errors, 1);
}

// What tells one bus from another: group and port; TTL and buffer options do not.
// The wall clock's utime is the system clock in microseconds since 1970: read between two
// readings of it, it lies between them (whole microseconds, so the bounds are inclusive).
TEST(Bus, WallClockUtimeIsTheSystemClockInMicroseconds) {
    const auto us = [] {
        return std::chrono::duration_cast<std::chrono::microseconds>(
                   std::chrono::system_clock::now().time_since_epoch())
            .count();
    };
    const int64_t before = us();
    const int64_t utime = bus::WallClockUtime();
    const int64_t after = us();
    EXPECT_LE(before, utime);
    EXPECT_LE(utime, after);
    EXPECT_GT(utime, 1'700'000'000'000'000) << "after 2023: microseconds, not seconds";
}

TEST(UdpmUrl, GroupAndPortAreTheBus) {
    auto a = bus::ParseUdpm("udpm://239.255.76.67:7668?ttl=1&recv_buf_size=4194304");
    ASSERT_TRUE(a.has_value());
    EXPECT_EQ(a->group, "239.255.76.67");
    EXPECT_EQ(a->port, 7668);
    EXPECT_EQ(a->options, "ttl=1&recv_buf_size=4194304");
    EXPECT_EQ(bus::FormatUdpm(*a), "udpm://239.255.76.67:7668?ttl=1&recv_buf_size=4194304");
    auto b = bus::ParseUdpm("udpm://239.255.76.67:7668?ttl=0");
    ASSERT_TRUE(b.has_value());
    EXPECT_TRUE(*a == *b);
    auto d = bus::ParseUdpm("udpm://239.255.76.67");  // LCM's default port
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(d->port, 7667);
    EXPECT_FALSE(*d == *b);
    for (const char* bad : {"memq://", "udpm://", "udpm://not.an.ip:7667", "udpm://239.255.76.67:",
                            "udpm://239.255.76.67:70000", "udpm://239.255.76.67:76x7"})
        EXPECT_FALSE(bus::ParseUdpm(bad).has_value()) << bad;
}

}  // namespace
}  // namespace gyrocal
