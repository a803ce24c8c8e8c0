// Every message type survives encode -> decode: decoding the builders' messages (every field
// set) and encoding them again gives the same bytes, so every field comes back, NaN bit patterns
// included; and a payload of one type does not decode as another (the fingerprint check the Bus
// relies on). Hostile lengths are refused in tests/lcmtypes/bus (decode_test, bus_test).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "gyrocal/analysis_t.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal {
namespace {

// Each type's examples: the builders' messages, and a second one where a field has another
// meaning to carry (ADC codes at their extremes, a chamber fault, motion and a gap in a plateau, a
// refused rotation, a full covariance, empty arrays, a stop event, an extrapolated rate, an empty
// batch, a leaving flow answer).
auto Examples() {
    using namespace testing;
    gyro_sample_t adc = Gyro("S07", 987654321);
    adc.supply_v = 5.01;
    adc.has_adc = true;
    adc.gyro_counts = 32767;
    adc.temp_counts = -12;
    adc.supply_counts = 65535;
    chamber_state_t faulted = Chamber(3);
    faulted.at_setpoint = false;
    faulted.fault = "setpoint 200 C outside -45..90 C";
    plateau_t imported = Plateau("S02", "R1", 10, 20);  // not from gyrocal-plateau
    imported.n_excluded_motion = 12;
    imported.seq_gaps = 1;
    sensitivity_point_t refused = Sensitivity("S04", "R1", 1, 2);
    refused.direction = -1;
    refused.accepted = false;
    refused.reject_reason = "sequence gap inside the move";
    coeff_set_t analysis = Coeffs("S01", "R1", 1234, {10, 20, 30}, {11, 12});
    analysis.source = "analysis:7";
    analysis.offset.covariance = {{1e-10, 1e-12, 0}, {1e-12, 1e-12, -1e-15}, {0, -1e-15, 1e-16}};
    analysis_t loop{};  // the fitter's closed loop (ANALYSIS_<id>)
    loop.utime = 1234, loop.sensor_id = "S01", loop.run_id = "R1", loop.coeff_set_id = 1234;
    loop.source = "closed-loop", loop.is_final = true, loop.outcome = "explained";
    loop.headline = "missing effect: supply, explained";
    loop.offset_rms_v_before = 1e-3, loop.offset_rms_v_after = 1e-4, loop.rate_rms_dps_before = 0.2;
    loop.rate_rms_dps_after = 0.02, loop.drift_dph_before = 80, loop.drift_dph_after = NAN;
    loop.floor_rate_rms_dps = 0.01, loop.floor_drift_dph = 5, loop.candidates_json = "[]";
    loop.added_json = "[]", loop.result_json = "{\"residual_bins\": {}}";
    rate_t outside = Rate("S01", 5);
    outside.temp_c = 70.0;
    outside.range_flag = 2;  // extrapolated
    flow_ack_t leaving = FlowAck(7);
    leaving.leaving = true;
    return std::make_tuple(
        std::vector{Gyro("S01", 7), adc}, std::vector{Encoder(-5000), Encoder(3)},
        std::vector{Chamber(2), faulted}, std::vector{ChamberCmd("R1")},
        std::vector{TurntableCmd("R1")},
        std::vector{RunEvent("R1", "start", {"S01", "S02"}), RunEvent("R1", "stop", {})},
        std::vector{Plateau("S02", "R1", 10, 20), imported}, std::vector{PlateauState("S03")},
        std::vector{Sensitivity("S04", "R1", 30, 40), refused},
        std::vector{Model("offset_v", {2.5, 1e-3, -2e-5})},
        std::vector{analysis, Coeffs("S01", "R1", 99, {}, {})},
        std::vector{Rate("S01", 5), outside}, std::vector{Status("gyrocal-fitter")},
        std::vector{Power("S01")}, std::vector{Noise("S01")}, std::vector{FitReport("S01")},
        std::vector{loop}, std::vector{GyroBatch("S01", 10, 16), GyroBatch("S01", 0, 0)},
        std::vector{EncoderBatch(3, 16)}, std::vector{RateBatch("S01", 5, 16)},
        std::vector{FlowMark(1)}, std::vector{leaving});
}

// The message types of Examples(), as gtest's type list, named by their LCM type names.
template <class Tuple>
struct TypesOf;
template <class... Msg>
struct TypesOf<std::tuple<std::vector<Msg>...>> {
    using type = ::testing::Types<Msg...>;
};
struct TypeName {
    template <class Msg>
    static std::string GetName(int) {
        return Msg::getTypeName();
    }
};

template <class Msg>
Msg Decoded(const std::vector<uint8_t>& bytes) {
    Msg out{};
    EXPECT_EQ(out.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
              static_cast<int>(bytes.size()));
    return out;
}

template <class Msg>
class RoundTrip : public ::testing::Test {};
TYPED_TEST_SUITE(RoundTrip, TypesOf<decltype(Examples())>::type, TypeName);

TYPED_TEST(RoundTrip, DecodingAndEncodingAgainGivesTheSameBytes) {
    const auto examples = Examples();
    for (const TypeParam& m : std::get<std::vector<TypeParam>>(examples)) {
        const std::vector<uint8_t> bytes = testing::EncodeMsg(m);
        EXPECT_EQ(testing::EncodeMsg(Decoded<TypeParam>(bytes)), bytes);
    }
}

TEST(NaN, SurvivesTheRoundTrip) {
    const gyrocal::gyro_sample_t g = testing::Gyro("S01", 0);
    ASSERT_TRUE(std::isnan(g.supply_v));
    EXPECT_TRUE(std::isnan(Decoded<gyro_sample_t>(testing::EncodeMsg(g)).supply_v));
}

TEST(Fingerprint, PayloadOfOneTypeDoesNotDecodeAsAnother) {
    std::vector<uint8_t> buf = testing::EncodeMsg(testing::Gyro("S01", 0));
    encoder_sample_t e;
    EXPECT_LT(e.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
    rate_t r;
    EXPECT_LT(r.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
}

}  // namespace
}  // namespace gyrocal
