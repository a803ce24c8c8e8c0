#include "processors/model/convert.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "tests/processors/model/test_models.hpp"

namespace gyrocal::model {
namespace {

using testing::ExpectSameModel;
using testing::ExpectSameSet;
using testing::Quadratic;

CoeffSet Set() {
    CoeffSet s;
    s.utime = 1'000'000'123'000'000;
    s.coeff_set_id = s.utime;
    s.sensor_id = "S01";
    s.run_id = "r1";
    s.source = "fitter";
    s.offset = Quadratic(kOffsetQuantity);
    s.sensitivity = Quadratic(kSensitivityQuantity);
    s.plateau_ids = {11, 22, 33};
    s.rotation_ids = {44, 55};
    return s;
}

TEST(Convert, ModelRoundTripsThroughModelTAndItsEncoding) {
    const Model m = Quadratic();
    const gyrocal::model_t msg = ToMsg(m);
    EXPECT_EQ(msg.num_terms, 3);
    // through the wire bytes, as a consumer sees it
    std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
    ASSERT_GE(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), 0);
    gyrocal::model_t decoded;
    ASSERT_GE(decoded.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
    ExpectSameModel(FromMsg(decoded), m);
}

TEST(Convert, CoeffSetRoundTrips) {
    const CoeffSet s = Set();
    ExpectSameSet(FromMsg(ToMsg(s)), s);
}

TEST(Convert, MismatchedArraysAndBadModelsAreRefusedNamingTheField) {
    auto refused = [](const gyrocal::coeff_set_t& msg, const std::string& words) {
        testing::ExpectRefused([&] { FromMsg(msg); }, words);
    };
    gyrocal::coeff_set_t msg = ToMsg(Set());
    msg.offset.num_terms = 4;
    refused(msg, "offset: offset_v: num_terms 4 does not match");
    msg = ToMsg(Set());
    msg.sensitivity.covariance[1].pop_back();
    refused(msg, "sensitivity: sensitivity_v_per_dps: covariance row 1 has 2 values");
    msg = ToMsg(Set());
    msg.sensitivity.term_names[0] = "x";
    refused(msg, "unknown term 'x'");
    msg = ToMsg(Set());
    msg.num_plateaus = 2;
    refused(msg, "num_plateaus 2 does not match plateau_ids (3)");
    msg = ToMsg(Set());
    msg.num_rotations = 5;
    refused(msg, "num_rotations 5");
    msg = ToMsg(Set());
    std::swap(msg.offset.quantity, msg.sensitivity.quantity);
    refused(msg, "quantity");
    msg = ToMsg(Set());
    msg.offset.num_terms = 0;
    msg.offset.term_names.clear();
    msg.offset.coeffs.clear();
    msg.offset.covariance.clear();
    refused(msg, "num_terms is 0");
}

TEST(Convert, ToMsgRefusesAnUnusableModelRatherThanEncodingHalfOfIt) {
    Model m = Quadratic();
    m.coeffs.resize(2);
    EXPECT_THROW(ToMsg(m), ModelError);
    CoeffSet s = Set();
    s.offset.quantity = "rate";
    EXPECT_THROW(ToMsg(s), ModelError);
}

}  // namespace
}  // namespace gyrocal::model
