// The leave-one-out outlier test and the lower-order fallbacks (fit/calibration_fit.hpp) and the
// separated-level count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/fit/calibration_fit.hpp"
#include "tests/processors/fit/synth.hpp"

namespace gyrocal::fit {
namespace {

using testing::Poly;

const Poly kTruth{25.0, {2.5, 4e-4, 3e-6}};
const std::vector<double> kSeven = {-40, -20, 0, 20, 40, 60, 85};

TEST(Levels, SeparatedCountIsTheLargestSubsetThatFarApart) {
    auto count = [](std::vector<double> t, double sep) {
        return SeparatedLevelCount(TemperatureLevels(t, 1.0), sep);
    };
    EXPECT_EQ(count({-11.9, 8, 22.9, 23.1, 27.8, 47, 67}, 5.0), 5);  // two levels 0.2 degC apart
    EXPECT_EQ(count({0, 4, 8, 12}, 5.0), 2);
    EXPECT_EQ(count({25, 28, 60}, 5.0), 2);
    EXPECT_EQ(count({}, 5.0), 0);
}

// GIVEN 2000 clean 7-point sets with honest stated errors
// THEN the share that loses a point is at most the family alpha 0.01: expected <= 20 of 2000,
// binomial sd 4.5; 38 is 4 sd above 20.
TEST(Outliers, CleanSetsRarelyLoseAPoint) {
    // Alone (c on its own 3 dof) and with the evidence of three clean units pooled (c on 12 more
    // dof, the chi-square they would bring): the test is calibrated either way.
    std::mt19937_64 rng(7);
    std::chi_squared_distribution<double> others(12);
    int lost = 0, lost_pooled = 0;
    for (int k = 0; k < 2000; ++k) {
        const auto pts = testing::Points(kTruth, kSeven, {2e-5}, rng);
        const CalibrationFit c = FitCalibration(pts, "offset_v", FitOptions{});
        ASSERT_TRUE(c.complete);
        lost += c.excluded.empty() ? 0 : 1;
        FitOptions pooled;
        pooled.pooled_chi2 = others(rng);
        pooled.pooled_dof = 12;
        lost_pooled += FitCalibration(pts, "offset_v", pooled).excluded.empty() ? 0 : 1;
    }
    std::printf("[ outliers ] clean 7-point sets that lost a point: %d of 2000 alone, %d pooled\n",
                lost, lost_pooled);
    EXPECT_LE(lost, 38);
    EXPECT_LE(lost_pooled, 38);
}

// With other units' evidence pooled (c ~ 1 on 9 more dof, as three clean units bring) a point
// 30 sigma off is excluded. Alone, c rests on the cubic reference's 2 dof (6 points left), the
// threshold is t_2 at 0.01/7 = 26.4: only a point ~40 sigma off stands out.
TEST(Outliers, APointThirtySigmaOffIsExcludedNamedAndTheFitRecovers) {
    std::mt19937_64 rng(11);
    auto pts = testing::Points(kTruth, kSeven, {2e-5}, rng);
    pts[3].y += 30 * 2e-5;  // 20 degC
    EXPECT_TRUE(FitCalibration(pts, "offset_v", FitOptions{}).excluded.empty());
    auto far = pts;
    far[3].y += 30 * 2e-5;  // 60 sigma
    EXPECT_EQ(FitCalibration(far, "offset_v", FitOptions{}).excluded.size(), 1u);
    FitOptions pooled;
    pooled.pooled_chi2 = 9.0;
    pooled.pooled_dof = 9;
    const CalibrationFit c = FitCalibration(pts, "offset_v", pooled);
    ASSERT_TRUE(c.complete);
    ASSERT_EQ(c.excluded.size(), 1u) << c.outlier_check;
    EXPECT_EQ(c.excluded[0].id, pts[3].id);
    EXPECT_GT(std::abs(c.excluded[0].statistic), c.excluded[0].threshold);
    EXPECT_NE(c.excluded[0].reason.find("leave-one-out"), std::string::npos);
    EXPECT_EQ(c.fit.used_ids.size(), 6u);
    EXPECT_NE(c.outlier_check.find("checked 6 points"), std::string::npos) << c.outlier_check;
    // the curve is back on the truth at 20 degC within 4 of its own sigma
    model::ModelInputs in;
    in.temp_c = 20;
    const model::Evaluation e = model::Evaluate(c.fit.model, in, model::RangePolicy::kClip);
    EXPECT_NEAR(e.value, kTruth(20), 4 * std::sqrt(e.variance));
    // AND with the test off the point is kept and pulls the curve by far more than that
    OutlierOptions off;
    off.enabled = false;
    const CalibrationFit kept = FitCalibration(pts, "offset_v", pooled, off);
    EXPECT_TRUE(kept.excluded.empty());
    EXPECT_EQ(kept.outlier_check, "not checked (disabled)");
}

// Two points off: alone, each masks the other (the fit without one still holds the other, whose
// scatter inflates c). With the evidence of clean units pooled (c ~ 1 on 12 more dof) both stand
// out; the limit (a quarter of 7 points: one) keeps the second, and says so.
TEST(Outliers, PooledEvidenceUnmasksAndTheExclusionLimitKeepsMostPoints) {
    std::mt19937_64 rng(13);
    auto pts = testing::Points(kTruth, kSeven, {2e-5}, rng);
    pts[2].y += 40 * 2e-5;
    pts[4].y -= 15 * 2e-5;
    EXPECT_TRUE(FitCalibration(pts, "offset_v", FitOptions{}).excluded.empty());
    FitOptions pooled;
    pooled.pooled_chi2 = 12.0;
    pooled.pooled_dof = 12;
    const CalibrationFit c = FitCalibration(pts, "offset_v", pooled);
    ASSERT_EQ(c.excluded.size(), 1u);
    EXPECT_EQ(c.excluded[0].id, pts[2].id);
    EXPECT_NE(c.outlier_check.find("exclusion limit"), std::string::npos) << c.outlier_check;
    OutlierOptions two;
    two.max_fraction = 0.3;  // two of seven
    EXPECT_EQ(FitCalibration(pts, "offset_v", pooled, two).excluded.size(), 2u);
}

TEST(Outliers, ThreeOrFourPointsCannotBeChecked) {
    std::mt19937_64 rng(17);
    const auto three = testing::Points(kTruth, {-10, 30, 60}, {2e-5}, rng);
    const CalibrationFit c3 = FitCalibration(three, "offset_v", FitOptions{});
    EXPECT_EQ(c3.fit.model.method, "3point");
    EXPECT_NE(c3.outlier_check.find("cannot check"), std::string::npos) << c3.outlier_check;
    const auto four = testing::Points(kTruth, {-10, 10, 30, 60}, {2e-5}, rng);
    FitOptions quad;
    quad.fixed_degree = 2;
    const CalibrationFit c4 = FitCalibration(four, "offset_v", quad);
    EXPECT_NE(c4.outlier_check.find("cannot check"), std::string::npos) << c4.outlier_check;
}

TEST(Fallback, TooFewTemperaturesGiveALineOrAMeanMarkedPartial) {
    std::mt19937_64 rng(19);
    // Two separated temperatures (25 and 28 are one): a line.
    const CalibrationFit line = FitCalibration(testing::Points(kTruth, {25, 28, 60}, {2e-5}, rng),
                                               "offset_v", FitOptions{});
    ASSERT_TRUE(line.fit.ok());
    EXPECT_FALSE(line.complete);
    EXPECT_EQ(line.fit.model.term_names, (std::vector<std::string>{"1", "dT"}));
    EXPECT_NE(line.partial_reason.find("too_few_temperatures"), std::string::npos);
    // One temperature: the weighted mean.
    const CalibrationFit mean =
        FitCalibration(testing::Points(kTruth, {25, 25.3}, {2e-5}, rng), "offset_v", FitOptions{});
    ASSERT_TRUE(mean.fit.ok());
    EXPECT_FALSE(mean.complete);
    EXPECT_EQ(mean.fit.model.method, "mean");
    // A narrow range (15..25 degC < 20): a line, and the reason says why.
    const CalibrationFit narrow = FitCalibration(testing::Points(kTruth, {15, 20, 25}, {2e-5}, rng),
                                                 "offset_v", FitOptions{});
    EXPECT_FALSE(narrow.complete);
    EXPECT_NE(narrow.partial_reason.find("range_too_narrow"), std::string::npos);
    // Non-finite input publishes nothing.
    auto bad = testing::Points(kTruth, {-10, 30, 60}, {2e-5}, rng);
    bad[1].y = NAN;
    EXPECT_FALSE(FitCalibration(bad, "offset_v", FitOptions{}).fit.ok());
}

// The run: the first and last plateaus at 22.9 and 23.1 degC sit 4.7 degC from the
// 27.8 degC plateau. Nothing is refused: the set is complete and spans the whole range.
TEST(Fallback, AReturnToTheStartIsData) {
    std::mt19937_64 rng(23);
    const auto pts =
        testing::Points(kTruth, {22.9, -11.9, 8.0, 27.8, 47.0, 67.0, 23.1}, {4e-5}, rng);
    const CalibrationFit c = FitCalibration(pts, "offset_v", FitOptions{});
    ASSERT_TRUE(c.complete) << c.partial_reason;
    EXPECT_EQ(c.fit.model.temp_min_c, -11.9);
    EXPECT_EQ(c.fit.model.temp_max_c, 67.0);
    EXPECT_EQ(c.fit.used_ids.size(), 7u);
}

}  // namespace
}  // namespace gyrocal::fit
