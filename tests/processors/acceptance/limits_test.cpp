// The limits file: a valid file round-trips; every bad input is an error naming the key (or the
// line and column) and what would be valid.
#include "processors/acceptance/limits.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace gyrocal::acceptance {
namespace {

// The error text of parsing `text`, "" when it parsed.
std::string ErrorOf(const std::string& text) {
    try {
        ParseLimits(text, "lim.json");
        return "";
    } catch (const LimitsError& e) {
        return e.what();
    }
}

TEST(Limits, AValidFileGivesEveryLimitAndRoundTrips) {
    const Limits l = ParseLimits(R"({"description": "prod", "max_residual_rms_over_floor": 2,
        "max_offset_change_dps": 3.5, "max_sensitivity_rel_uncertainty_pct": 0.5, "min_plateaus": 5,
        "min_turns": 10, "no_unexplained_residual": true, "max_heldout_rate_rms_dps": 0.05,
        "max_heldout_drift_dph": 60})",
                                 "lim.json");
    EXPECT_EQ(*l.max_heldout_rate_rms_dps, 0.05);
    EXPECT_EQ(*l.max_heldout_drift_dph, 60.0);
    EXPECT_EQ(l.description, "prod");
    EXPECT_EQ(*l.max_residual_rms_over_floor, 2.0);
    EXPECT_EQ(*l.max_offset_change_dps, 3.5);
    EXPECT_EQ(*l.max_sensitivity_rel_uncertainty_pct, 0.5);
    EXPECT_EQ(*l.min_plateaus, 5);
    EXPECT_EQ(*l.min_turns, 10);
    EXPECT_TRUE(l.no_unexplained_residual);
    const Limits back = FromJson(ToJson(l), "copy");
    EXPECT_EQ(ToJson(back), ToJson(l));
    // A limit not given is not checked; a count written 5.0 is a whole number.
    const Limits one = ParseLimits(R"({"min_turns": 6.0})", "x");
    EXPECT_EQ(*one.min_turns, 6);
    EXPECT_FALSE(one.max_offset_change_dps.has_value());
    EXPECT_EQ(ToJson(one).size(), 1u);
}

TEST(Limits, UnknownKeyIsNamedWithTheValidKeys) {
    const std::string e = ErrorOf(R"({"max_offset_change": 3})");
    EXPECT_NE(e.find("lim.json: unknown key 'max_offset_change'"), std::string::npos) << e;
    EXPECT_NE(e.find("max_offset_change_dps"), std::string::npos) << e;
}

TEST(Limits, WrongTypesAndInvalidValuesNameTheKeyAndWhatIsValid) {
    // (the file's text, what its error says)
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"max_offset_change_dps": "3"})",
         "key 'max_offset_change_dps': expected a number >= 0, got string"},
        {R"({"max_offset_change_dps": -1})",
         "key 'max_offset_change_dps': -1 is not valid; expected a number >= 0"},
        {R"({"min_plateaus": 2.5})", "key 'min_plateaus': expected a whole number >= 1"},
        {R"({"min_turns": 0})", "key 'min_turns': 0 is not valid; expected a whole number from 1"},
        {R"({"no_unexplained_residual": "yes"})",
         "key 'no_unexplained_residual': expected true or false, got string"},
        {R"({"max_heldout_drift_dph": -2})",
         "key 'max_heldout_drift_dph': -2 is not valid; expected a number >= 0"},
        {R"({"description": 3, "min_turns": 1})", "key 'description': expected a string"}};
    for (const auto& [text, says] : cases) {
        const std::string e = ErrorOf(text);
        EXPECT_NE(e.find(says), std::string::npos) << text << ": " << e;
    }
}

TEST(Limits, NotAnObjectNoLimitOrNotJsonAreRefused) {
    std::string e = ErrorOf("[1, 2]");
    EXPECT_NE(e.find("expected a JSON object of limits"), std::string::npos) << e;
    e = ErrorOf(R"({"description": "only words", "no_unexplained_residual": false})");
    EXPECT_NE(e.find("no limit given"), std::string::npos) << e;
    e = ErrorOf("{\n  \"min_turns\": 6,\n}\n");
    EXPECT_NE(e.find("lim.json: not valid JSON"), std::string::npos) << e;
    EXPECT_NE(e.find("line 3, column 1"), std::string::npos) << e;
    try {
        LoadLimitsFile("/nonexistent/limits.json");
        FAIL();
    } catch (const LimitsError& x) {
        EXPECT_NE(std::string(x.what()).find("/nonexistent/limits.json: cannot be read"),
                  std::string::npos)
            << x.what();
    }
}

TEST(Limits, LoadsAFile) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("gyrocal_limits_" + std::to_string(::getpid()) + ".json");
    std::ofstream(path) << R"({"min_plateaus": 5})";
    EXPECT_EQ(*LoadLimitsFile(path.string()).min_plateaus, 5);
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace gyrocal::acceptance
