// calibrate's final verdict (tools/cli/final_verdict): from the sets and FIT_<id> reports a
// run left, which units are complete, what the table marks, and what exit 3 explains. Pure
// bookkeeping over messages; every case below has one right answer.
#include "tools/supervisor/final_verdict.hpp"

#include <gtest/gtest.h>

#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::supervisor {
namespace {

coeff_set_t Set(const std::string& id, int64_t set_id, int offset_terms) {
    coeff_set_t c{};
    c.sensor_id = id;
    c.coeff_set_id = set_id;
    c.source = "fitter";
    c.offset.method = "wls";
    c.offset.num_terms = static_cast<int16_t>(offset_terms);
    c.offset.temp_min_c = -10.0;
    c.offset.temp_max_c = 70.0;
    c.sensitivity.method = "wls";
    c.sensitivity.num_terms = 3;
    c.sensitivity.temp_min_c = -10.0;
    c.sensitivity.temp_max_c = 70.0;
    return c;
}

// A final report of set `set_id`.
fit_report_t Report(const std::string& id, int64_t set_id, const std::string& status,
                    const std::string& reason) {
    fit_report_t r = testing::FitReport(id);
    r.coeff_set_id = set_id;
    r.status = status;
    r.reason = reason;
    return r;
}

TEST(FinalVerdict, EveryUnitCompleteAndFinalIsExitZeroWithNoLabelAndNothingToExplain) {
    const std::map<std::string, coeff_set_t> newest = {{"U1", Set("U1", 50, 3)},
                                                       {"U2", Set("U2", 50, 4)}};
    const std::set<std::string> finals = {"U1", "U2"};
    const std::map<std::string, fit_report_t> reports = {{"U1", Report("U1", 50, "complete", "")},
                                                         {"U2", Report("U2", 50, "complete", "")}};
    const FinalVerdict v{{"U1", "U2"}, newest, finals, reports};
    EXPECT_TRUE(v.AllComplete());
    EXPECT_EQ(v.Labels(), (std::map<std::string, std::string>{{"U1", ""}, {"U2", ""}}));
    EXPECT_EQ(v.Explain(), "");
}

TEST(FinalVerdict, APartialUnitIsNamedWithItsReasonAndWhatWasPublished) {
    // GIVEN U2's final fit fell back to a constant offset, U1 complete
    const std::map<std::string, coeff_set_t> newest = {{"U1", Set("U1", 50, 3)},
                                                       {"U2", Set("U2", 50, 1)}};
    const std::set<std::string> finals = {"U1", "U2"};
    const std::map<std::string, fit_report_t> reports = {
        {"U1", Report("U1", 50, "complete", "")},
        {"U2", Report("U2", 50, "partial", "offset: one temperature level, constant offset only")}};
    const FinalVerdict v{{"U1", "U2"}, newest, finals, reports};
    // THEN not all complete (exit 3), the table marks U2 only, the explanation names U2, why, what
    EXPECT_FALSE(v.AllComplete());
    EXPECT_EQ(v.Labels().at("U1"), "");
    EXPECT_EQ(v.Labels().at("U2"), "PARTIAL: offset: one temperature level, constant offset only");
    const std::string e = v.Explain();
    EXPECT_EQ(e.find("U1"), std::string::npos) << e;
    EXPECT_NE(e.find("unit U2: PARTIAL calibration: offset: one temperature level"),
              std::string::npos)
        << e;
    EXPECT_NE(e.find("published set 50: offset wls with 1 terms over -10.0..70.0 C"),
              std::string::npos)
        << e;
}

TEST(FinalVerdict, AStaleSetIsNeverShownAsFinal) {
    // GIVEN U1's newest set came before the stop and the final report published none
    const std::map<std::string, coeff_set_t> newest = {{"U1", Set("U1", 20, 3)}};
    const std::set<std::string> finals;
    const std::map<std::string, fit_report_t> reports = {
        {"U1", Report("U1", -1, "none", "no plateau")}};
    const FinalVerdict v{{"U1"}, newest, finals, reports};
    EXPECT_FALSE(v.AllComplete());
    EXPECT_EQ(v.Labels().at("U1").rfind("NOT FINAL", 0), 0u) << v.Labels().at("U1");
    const std::string e = v.Explain();
    EXPECT_NE(e.find("unit U1: no calibration: no plateau"), std::string::npos) << e;
    EXPECT_NE(e.find("the newest set (set 20: offset wls with 3 terms"), std::string::npos) << e;
    EXPECT_NE(e.find(") is from before the run's end"), std::string::npos) << e;
}

TEST(FinalVerdict, AUnitWithoutAFinalReportOrAnyUnitsIsNotComplete) {
    const std::map<std::string, coeff_set_t> newest;
    const std::set<std::string> finals;
    const std::map<std::string, fit_report_t> reports;
    const FinalVerdict v{{"U3"}, newest, finals, reports};
    EXPECT_FALSE(v.AllComplete());
    EXPECT_NE(v.Explain().find("unit U3: no final report from the fitter"), std::string::npos);
    EXPECT_NE(v.Explain().find("nothing published"), std::string::npos);
    // no unit at all is no calibration, not a vacuous success
    EXPECT_FALSE((FinalVerdict{{}, newest, finals, reports}.AllComplete()));
}

TEST(FinalVerdict, ANewerSetThanTheFinalReportsIsMarked) {
    const std::map<std::string, coeff_set_t> newest = {{"U1", Set("U1", 60, 3)}};
    const std::set<std::string> finals = {"U1"};
    const std::map<std::string, fit_report_t> reports = {{"U1", Report("U1", 50, "complete", "")}};
    const FinalVerdict v{{"U1"}, newest, finals, reports};
    EXPECT_EQ(v.Labels().at("U1"), "NOT FINAL: a newer set than the final report's arrived");
}

}  // namespace
}  // namespace gyrocal::supervisor
