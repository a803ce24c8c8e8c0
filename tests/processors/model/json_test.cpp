#include "processors/model/json.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "processors/model/inputs.hpp"
#include "tests/processors/model/test_models.hpp"

namespace gyrocal::model {
namespace {

using testing::Quadratic;

TEST(Json, ModelRoundTripsThroughText) {
    Model m = Quadratic();
    m.residual_rms = NAN;  // JSON has no NaN: written null, read back NaN
    m.covariance(0, 1) = NAN;
    const std::string text = ToJson(m).dump();
    EXPECT_NE(text.find("null"), std::string::npos);
    const Model back = ModelFromJson(nlohmann::json::parse(text));
    EXPECT_EQ(back.term_names, m.term_names);
    EXPECT_EQ(back.coeffs, m.coeffs);  // doubles survive nlohmann's shortest round-trip printing
    EXPECT_TRUE(std::isnan(back.residual_rms));
    EXPECT_TRUE(std::isnan(back.covariance(0, 1)));
    EXPECT_EQ(back.covariance(2, 2), m.covariance(2, 2));
    EXPECT_EQ(back.method, "wls");
}

// The lag product's name (with '*' and a parameter) is stored as written and resolves back to the
// same kind and time constant.
TEST(Json, LagProductTermRoundTripsThroughText) {
    Model m = Quadratic();
    m.term_names = {"1", "dTdt(15.2)", "dT*dTdt(15.2)"};
    const Model back = ModelFromJson(nlohmann::json::parse(ToJson(m).dump()));
    EXPECT_EQ(back.term_names, m.term_names);
    EXPECT_EQ(back.coeffs, m.coeffs);
    const std::vector<ResolvedTerm> t = ResolveTerms(back.term_names);
    EXPECT_EQ(t[2].c.kind, GYROCAL_TERM_DT_DTDT);
    EXPECT_EQ(t[2].c.param, 15.2);
    EXPECT_EQ(TrackerConfigFor(back).rate_tau_s, 15.2);
}

TEST(Json, CoeffSetRoundTrips) {
    CoeffSet s;
    s.utime = 5;
    s.coeff_set_id = 5;
    s.sensor_id = "S02";
    s.run_id = "r";
    s.source = "analysis:3";
    s.offset = Quadratic(kOffsetQuantity);
    s.sensitivity = Quadratic(kSensitivityQuantity);
    s.plateau_ids = {1, 2};
    const CoeffSet back = CoeffSetFromJson(nlohmann::json::parse(ToJson(s).dump()));
    EXPECT_EQ(back.source, "analysis:3");
    EXPECT_EQ(back.plateau_ids, s.plateau_ids);
    EXPECT_TRUE(back.rotation_ids.empty());
    EXPECT_EQ(back.sensitivity.coeffs, s.sensitivity.coeffs);
}

TEST(Json, BadFieldsAreNamed) {
    auto refused = [](const nlohmann::json& j, const std::string& words) {
        testing::ExpectRefused([&] { ModelFromJson(j); }, words);
    };
    nlohmann::json j = ToJson(Quadratic());
    j.erase("t0_c");
    refused(j, "model.t0_c: missing");
    j = ToJson(Quadratic());
    j["coeffs"][1] = "x";
    refused(j, "model.coeffs[1]");
    j = ToJson(Quadratic());
    j["covariance"][2] = {1.0};
    refused(j, "model.covariance[2]");
    j = ToJson(Quadratic());
    j["term_names"][0] = "cubic";
    refused(j, "unknown term 'cubic'");
    refused(nlohmann::json::array(), "must be a JSON object");
}

}  // namespace
}  // namespace gyrocal::model
