// The LCM log reader (producers/log_source/lcm_log.hpp) on files written here byte by byte in the
// format lcm-logger writes: events come back whole and in order; damage is an error that names
// the file and the byte, never a huge allocation or a silent stop.
#include "producers/log_source/lcm_log.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "tests/producers/log_source/log_writer.hpp"

namespace gyrocal::log_source {
namespace {

TEST(LcmLog, EventsComeBackWholeAndInOrder) {
    std::ostringstream out;
    test::WriteEvent(out, 0, 1000, "GYRO_L1", {1, 2, 3});
    test::WriteEvent(out, 1, 2000, "RUN_EVENT", {});
    std::istringstream in(out.str());
    LogReader r(in, "x.lcmlog");
    const auto a = r.Next();
    ASSERT_TRUE(a);
    EXPECT_EQ(a->event_number, 0);
    EXPECT_EQ(a->utime, 1000);
    EXPECT_EQ(a->channel, "GYRO_L1");
    EXPECT_EQ(a->data, (std::vector<uint8_t>{1, 2, 3}));
    EXPECT_EQ(r.offset(), 28 + 7 + 3);
    const auto b = r.Next();
    ASSERT_TRUE(b);
    EXPECT_EQ(b->channel, "RUN_EVENT");
    EXPECT_TRUE(b->data.empty());
    EXPECT_FALSE(r.Next());
}

TEST(LcmLog, DamageIsAnErrorNamingTheFileAndTheByte) {
    std::ostringstream out;
    test::WriteEvent(out, 0, 1000, "GYRO_L1", {1, 2, 3});
    const std::string good = out.str();
    auto error_of = [](const std::string& bytes) -> std::string {
        std::istringstream in(bytes);
        LogReader r(in, "x.lcmlog");
        try {
            while (r.Next()) {
            }
        } catch (const LogError& e) {
            return e.what();
        }
        return "";
    };
    // Cut inside the second event's data, inside a header, a wrong sync word, a huge length.
    std::ostringstream two;
    test::WriteEvent(two, 1, 2000, "GYRO_L1", std::vector<uint8_t>(100, 7));
    EXPECT_NE(error_of(good + two.str().substr(0, 60))
                  .find("x.lcmlog: byte 38: the file ends "
                        "inside an event (GYRO_L1)"),
              std::string::npos);
    EXPECT_NE(error_of(good + two.str().substr(0, 10))
                  .find("byte 38: the file ends inside an event header"),
              std::string::npos);
    std::string bad_sync = good;
    bad_sync[0] = 0;
    EXPECT_NE(error_of(bad_sync).find("byte 0: no sync word"), std::string::npos);
    std::string huge = good;
    huge[24] = 0x7f;  // the data length's first byte: 2 GB
    EXPECT_NE(error_of(huge).find("data length"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::log_source
