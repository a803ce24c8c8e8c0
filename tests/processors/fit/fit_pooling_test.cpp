// Pooling of overdispersion only among units that agree (fit/pooling.hpp), and repeatability at
// revisited temperatures (fit/repeatability.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/fit/pooling.hpp"
#include "processors/fit/repeatability.hpp"

namespace gyrocal::fit {
namespace {

// chi2 on dof of a unit whose errors are understated by sqrt(c).
UnitEvidence Draw(const std::string& id, double c, int dof, std::mt19937_64& rng) {
    std::chi_squared_distribution<double> chi2(dof);
    return {id, c * chi2(rng), dof};
}

TEST(Pool, UnitsWithACommonFactorAreRarelySplit) {
    // GIVEN 1000 runs of 4 units sharing c = 3 on 3 dof each
    std::mt19937_64 rng(5);
    int split = 0;
    for (int k = 0; k < 1000; ++k) {
        std::vector<UnitEvidence> u;
        for (int i = 0; i < 4; ++i) u.push_back(Draw("S" + std::to_string(i), 3.0, 3, rng));
        split += Pool::Decide(u).left_out().empty() ? 0 : 1;
    }
    // THEN at most alpha = 1 % of them lose a unit (Bonferroni keeps it at or below): <= 10
    // expected, binomial sd 3.2; 23 is 4 sd above.
    EXPECT_LE(split, 23);
}

TEST(Pool, ABadUnitIsLeftOutAndGivesNothing) {
    std::mt19937_64 rng(9);
    std::vector<UnitEvidence> u = {Draw("S1", 2, 4, rng),
                                   Draw("S2", 2, 4, rng),
                                   Draw("S3", 2, 4, rng),
                                   {"S4", 900.0, 4}};  // ~100x
    const Pool pool = Pool::Decide(u);
    ASSERT_EQ(pool.left_out().count("S4"), 1u);
    EXPECT_NE(pool.left_out().at("S4").find("disagrees"), std::string::npos);
    EXPECT_EQ(pool.agreeing(), 3);
    // S1 pools S2 and S3 only; S4 pools nothing
    const PooledEvidence e1 = pool.For("S1");
    EXPECT_EQ(e1.dof, 8);
    EXPECT_DOUBLE_EQ(e1.chi2, u[1].chi2 + u[2].chi2);
    EXPECT_EQ(pool.For("S4").dof, 0);
    // a unit without dof (three points) gets the whole pool
    EXPECT_EQ(pool.For("S5").dof, 12);
}

Repeat Only(const std::vector<Repeat>& r) {
    EXPECT_EQ(r.size(), 1u);
    return r.empty() ? Repeat{} : r[0];
}

model::Model Line(const char* quantity, double c0, double c1) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = {"1", "dT"};
    m.coeffs = Eigen::Vector2d(c0, c1);
    m.covariance = Eigen::Matrix2d::Zero();
    m.t0_c = 25;
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    m.method = "wls";
    return m;
}

FitPoint P(int64_t id, double t, double y, double s) {
    FitPoint p;
    p.id = id;
    p.inputs.temp_c = t;
    p.y = y;
    p.sigma_y = s;
    return p;
}

TEST(Repeatability, AReturnIsComparedWithTheModelStepTakenOut) {
    const model::Model off = Line("offset_v", 2.5, 1e-3);  // 1 mV/K
    const model::Model sens = Line("sensitivity_v_per_dps", 0.006, 0.0);
    // 25 (start), -10, 70, back at 25.4: the model step 0.4 mV is taken out, leaving +0.2 mV.
    const std::vector<FitPoint> pts = {P(1, 25.0, 2.5, 3e-5), P(2, -10, 2.465, 3e-5),
                                       P(3, 70, 2.545, 3e-5),
                                       P(4, 25.4, 2.5 + 0.4e-3 + 0.2e-3, 4e-5)};
    const Repeat r = Only(Repeatability(pts, off, sens));
    EXPECT_EQ(r.first_id, 1);
    EXPECT_EQ(r.second_id, 4);
    EXPECT_NEAR(r.diff_v, 0.2e-3, 1e-12);
    EXPECT_NEAR(r.diff_sigma_v, 5e-5, 1e-15);
    EXPECT_NEAR(r.diff_dps, 0.2e-3 / 0.006, 1e-9);
    EXPECT_NEAR(r.z, 4.0, 1e-9);
    EXPECT_EQ(r.first_approach, 0);    // the run's first plateau
    EXPECT_EQ(r.second_approach, -1);  // from 70 degC: from hotter
    EXPECT_NE(r.verdict.find("not repeatable"), std::string::npos) << r.verdict;
    EXPECT_NE(r.verdict.find("drift"), std::string::npos) << r.verdict;
}

TEST(Repeatability, OppositeApproachesPointAtHysteresisAndReplicatesAreNoReturn) {
    const model::Model off = Line("offset_v", 2.5, 0.0);
    const model::Model sens = Line("sensitivity_v_per_dps", 0.006, 0.0);
    // 0 -> 30 (from colder) -> 30 again (same visit) -> 60 -> 30 (from hotter), 5 sigma apart
    const std::vector<FitPoint> pts = {P(1, 0, 2.5, 1e-5), P(2, 30, 2.5, 1e-5),
                                       P(3, 30.2, 2.5, 1e-5), P(4, 60, 2.5, 1e-5),
                                       P(5, 30.1, 2.5 + 5 * std::sqrt(2) * 1e-5, 1e-5)};
    const Repeat r = Only(Repeatability(pts, off, sens));
    EXPECT_EQ(r.first_id, 3);  // the latest earlier visit's last plateau
    EXPECT_EQ(r.second_id, 5);
    EXPECT_EQ(r.first_approach, 1);
    EXPECT_EQ(r.second_approach, -1);
    EXPECT_NEAR(r.z, 5.0, 1e-9);
    EXPECT_NE(r.verdict.find("hysteresis"), std::string::npos) << r.verdict;
    // within 3 sigma: repeatable
    std::vector<FitPoint> close = pts;
    close[4].y = 2.5 + 1e-5;
    EXPECT_NE(Only(Repeatability(close, off, sens)).verdict.find("repeatable within"),
              std::string::npos);
}

}  // namespace
}  // namespace gyrocal::fit
