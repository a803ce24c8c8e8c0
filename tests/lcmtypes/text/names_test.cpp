#include "lcmtypes/text/names.hpp"

#include <gtest/gtest.h>

namespace gyrocal::text {
namespace {

enum class Color { kRed, kGreen, kBlue, kUnnamed };
constexpr NameTable<Color, 3> kColorNames{
    {{Color::kRed, "red"}, {Color::kGreen, "green"}, {Color::kBlue, "blue"}}};

// The tables are constexpr: the code that names a value can run at compile time (checked here,
// where a failure stops the build).
static_assert(ValueOf(kColorNames, "blue") == Color::kBlue);
static_assert(NameOf(kColorNames, Color::kGreen)[0] == 'g');

TEST(Names, EveryValueInTheTablePrintsAsItsNameAndParsesBack) {
    for (const auto& [value, name] : kColorNames) {
        EXPECT_STREQ(NameOf(kColorNames, value), name);
        EXPECT_EQ(ValueOf(kColorNames, name), value);
    }
}

TEST(Names, AValueMissingFromTheTablePrintsAsTheMissingText) {
    EXPECT_STREQ(NameOf(kColorNames, Color::kUnnamed), "?");
    EXPECT_STREQ(NameOf(kColorNames, Color::kUnnamed, "none"), "none");
}

TEST(Names, ParsingIsExactAndCaseSensitive) {
    EXPECT_FALSE(ValueOf(kColorNames, "Red").has_value());
    EXPECT_FALSE(ValueOf(kColorNames, "red ").has_value());
    EXPECT_FALSE(ValueOf(kColorNames, "").has_value());
}

}  // namespace
}  // namespace gyrocal::text
