#include "processors/model/terms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "processors/model/model.hpp"

namespace gyrocal::model {
namespace {

double Term(const std::string& name, double dT, const ModelInputs& in) {
    ResolvedTerm t;
    std::string error;
    EXPECT_TRUE(ResolveTerm(name, &t, &error)) << error;
    return t(dT, in);
}

TEST(Terms, PolynomialAndInputTermsHaveTheirDocumentedValues) {
    ModelInputs in;
    in.dtemp_dt_c_per_s = 0.02;
    in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    in.supply_v = kNominalSupplyV + 0.1;
    in.heating = -1;
    in.branch = -0.4;
    in.branch_width_c = GYROCAL_SIGN_BRANCH_WIDTH_C;
    in.direction = 1;
    in.time_since_power_s = 600;
    EXPECT_EQ(Term("1", 3.0, in), 1.0);
    EXPECT_EQ(Term("dT", 3.0, in), 3.0);
    EXPECT_EQ(Term("dT^2", 3.0, in), 9.0);
    EXPECT_EQ(Term("dT^3", -2.0, in), -8.0);
    EXPECT_EQ(Term("dTdt", 3.0, in), 0.02);
    EXPECT_EQ(Term("dTdt(5)", 3.0, in), 0.02);         // the default time constant written out
    EXPECT_NEAR(Term("supply", 3.0, in), 0.1, 1e-15);  // about the nominal supply
    EXPECT_EQ(Term("heating", 3.0, in), -1.0);         // sign-only: the side last reached
    EXPECT_EQ(Term("heating(1)", 3.0, in), -0.4);      // the continuous branch of width 1
    EXPECT_EQ(Term("direction", 3.0, in), 1.0);
    EXPECT_NEAR(Term("warmup(300)", 3.0, in), std::exp(-2.0), 1e-15);
}

// dT x dT/dt (a thermometer lagging the die on a curved offset): by hand at a point where both
// factors are nonzero, exact in binary (-2.5 x 0.125 = -0.3125); the tracker's time constant must
// be the one the name says, as for dTdt; the polynomial's dT is the one it multiplies.
TEST(Terms, LagProductIsDTTimesTheRateTrackedWithItsTimeConstant) {
    ModelInputs in;
    in.temp_c = 22.5;
    in.dtemp_dt_c_per_s = 0.125;
    in.rate_tau_s = 20.0;
    EXPECT_EQ(Term("dT*dTdt(20)", -2.5, in), -0.3125);
    EXPECT_EQ(Term("dT*dTdt(20)", 4.0, in), 0.5);
    EXPECT_EQ(Term("dT*dTdt(20)", 0.0, in), 0.0);              // at t0 nothing
    EXPECT_TRUE(std::isnan(Term("dT*dTdt", -2.5, in)));        // 5 s meant, 20 s tracked
    EXPECT_TRUE(std::isnan(Term("dT*dTdt(15.2)", -2.5, in)));  // another tau
    in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    EXPECT_EQ(Term("dT*dTdt", -2.5, in), -0.3125);
    EXPECT_EQ(Term("dT*dTdt(5)", -2.5, in), -0.3125);
    EXPECT_TRUE(std::isnan(Term("dT*dTdt", 1.0, ModelInputs())));  // rate unknown
    ResolvedTerm t;
    ASSERT_TRUE(ResolveTerm(LagProductTerm(15.24), &t, nullptr));
    EXPECT_EQ(t.c.kind, GYROCAL_TERM_DT_DTDT);
    EXPECT_EQ(t.c.param, 15.2);
    EXPECT_EQ(LagProductTerm(15.24), "dT*dTdt(15.2)");
    EXPECT_EQ(ParamTerm("dT*dTdt", 15.24), LagProductTerm(15.24));
    EXPECT_EQ(t.def->unit, "degC^2/s");
}

// Exported firmware headers store a term's kind by number: the kinds that existed before the lag
// product keep theirs, and the product is the newest, so a firmware built from an older copy of
// gyrocal_model.h reaches its `default` (NaN) for it, never another term's value.
TEST(Terms, KindNumbersAreStableAndTheLagProductIsAppended) {
    EXPECT_EQ(GYROCAL_TERM_ONE, 0);
    EXPECT_EQ(GYROCAL_TERM_DTDT, 4);
    EXPECT_EQ(GYROCAL_TERM_KNOT_BELOW, 11);
    EXPECT_EQ(GYROCAL_TERM_DT_DTDT, 12);
    const gyrocal_term_t unknown{GYROCAL_TERM_DT_DTDT + 1, 0.0};
    const ModelInputs in;
    EXPECT_TRUE(std::isnan(gyrocal_term_value(&unknown, 1.0, &in)));
}

TEST(Terms, InputsTrackedWithAnotherParameterAreNotUsed) {
    ModelInputs in;
    in.dtemp_dt_c_per_s = 0.02;
    in.rate_tau_s = 20.0;
    in.branch = 0.5;
    in.heating = 1.0;
    in.branch_width_c = 2.0;
    EXPECT_TRUE(std::isnan(Term("dTdt", 0.0, in)));  // 5 s meant, 20 s tracked
    EXPECT_EQ(Term("dTdt(20)", 0.0, in), 0.02);
    EXPECT_TRUE(std::isnan(Term("heating(2.5)", 0.0, in)));  // 2.5 degC meant, 2 tracked
    EXPECT_TRUE(std::isnan(Term("heating", 0.0, in)));       // the sign-only form is 1 degC
    EXPECT_EQ(Term("heating(2)", 0.0, in), 0.5);
}

TEST(Terms, MissingInputGivesNaNNotAWrongNumber) {
    ModelInputs in;  // only temperature-free terms known
    EXPECT_TRUE(std::isnan(Term("dTdt", 1.0, in)));
    EXPECT_TRUE(std::isnan(Term("supply", 1.0, in)));
    EXPECT_TRUE(std::isnan(Term("heating", 1.0, in)));
    EXPECT_TRUE(std::isnan(Term("warmup(60)", 1.0, in)));
}

// A knot is relative to t0 and may be on either side of it: zero on one side of the knot, the
// cube of the distance on the other (values exact in binary).
TEST(Terms, SplineKnotsAreZeroOnOneSideAndCubicOnTheOther) {
    const ModelInputs in;  // a static temperature shape needs no other input
    EXPECT_EQ(Term("knot_above(5)", 3.0, in), 0.0);
    EXPECT_EQ(Term("knot_above(5)", 5.0, in), 0.0);
    EXPECT_EQ(Term("knot_above(5)", 7.0, in), 8.0);
    EXPECT_EQ(Term("knot_above(-2.5)", -0.5, in), 8.0);
    EXPECT_EQ(Term("knot_below(-2.5)", -4.5, in), 8.0);
    EXPECT_EQ(Term("knot_below(-2.5)", 0.0, in), 0.0);
    EXPECT_EQ(Term("knot_below(0)", -1.0, in), 1.0);
    EXPECT_EQ(KnotAboveTerm(12.345), "knot_above(12.3)");
    EXPECT_EQ(KnotBelowTerm(-3.04), "knot_below(-3)");
    EXPECT_EQ(KnotBelowTerm(-0.01), "knot_below(0)");  // never "-0"
    for (const char* bad : {"knot_above", "knot_above()", "knot_above(x)", "knot_below(inf)"}) {
        std::string error;
        EXPECT_FALSE(ResolveTerm(bad, nullptr, &error)) << bad;
        EXPECT_FALSE(error.empty()) << bad;
    }
}

TEST(Terms, ParametricNamesAreWrittenOneWay) {
    EXPECT_EQ(WarmupTerm(407.3), "warmup(407)");
    EXPECT_EQ(BranchTerm(2.25), "heating(2.25)");
    EXPECT_EQ(RateTerm(5.0), "dTdt(5)");
    EXPECT_EQ(ParamTerm("warmup", 407.3), WarmupTerm(407.3));
    EXPECT_EQ(ParamTerm("heating", 2.25), BranchTerm(2.25));
    EXPECT_EQ(ParamTerm("knot_below", -3.04), KnotBelowTerm(-3.04));
    EXPECT_THROW(ParamTerm("supply", 1.0), std::invalid_argument);
    ResolvedTerm t;
    ASSERT_TRUE(ResolveTerm(BranchTerm(1.2345), &t, nullptr));
    EXPECT_EQ(t.c.kind, GYROCAL_TERM_BRANCH);
    EXPECT_EQ(t.c.param, 1.23);
}

TEST(Terms, UnknownOrMalformedNamesAreRefusedWithTheKnownList) {
    for (const char* bad :
         {"dT^4", "", "warmup", "warmup()", "warmup(-1)", "warmup(abc)", "dT(3)", "1(", "supply(2)",
          "heating(0)", "dTdt(-5)", "dT*dTdt(0)", "dT*dTdt(-5)", "dT*dTdt()"}) {
        std::string error;
        EXPECT_FALSE(ResolveTerm(bad, nullptr, &error)) << bad;
        EXPECT_FALSE(error.empty()) << bad;
    }
    std::string error;
    ResolveTerm("dT^4", nullptr, &error);
    EXPECT_NE(error.find("dT^3"), std::string::npos) << error;  // lists the known names
    EXPECT_THROW(ResolveTerms({"1", "bogus"}), ModelError);
}

TEST(Terms, PolynomialTermNames) {
    EXPECT_EQ(PolynomialTerms(2), (std::vector<std::string>{"1", "dT", "dT^2"}));
    EXPECT_THROW(PolynomialTerms(4), std::invalid_argument);
}

}  // namespace
}  // namespace gyrocal::model
