// An effect outside the analysis' candidate list, across real processes: the rig's null ages
// (`--effect aging=...`, announced on no channel), the whole graph calibrates the declared
// quadratic model, and `gyrocal analyze` on the recorded run must print a verdict that names no
// candidate: "unexplained residual", traced to the time channel. Ports 8000-8002, this file's
// own: one per calibration, because CTest runs this file's tests in parallel (-j) and two graphs on
// one port would record each other's samples as one run's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "lcmtypes/launch/child_process.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

// No analysis of `run` stored an extended set: the only set an analysis points to is the fitter's
// closed-loop one (the run's final set, every still sample), with the declared offset terms only.
void ExpectOnlyTheDeclaredClosedLoopSet(Sql& sql, const std::string& run) {
    EXPECT_EQ(sql.Int("SELECT count(*) FROM analyses a JOIN coeff_sets c USING(coeff_row_id) WHERE "
                      "a.run_id='" +
                      run + "' AND c.source != 'closed-loop'"),
              0);
    EXPECT_EQ(
        sql.Rows("SELECT group_concat(term_name, ',') FROM (SELECT term_name FROM coeff_terms t "
                 "JOIN coeff_sets c USING(coeff_row_id) WHERE c.run_id='" +
                 run + "' AND c.source='closed-loop' AND t.role='offset' ORDER BY term_index)")
            .at(0)
            .at(0),
        "1,dT,dT^2");
}

std::string LineStartingWith(const std::string& text, const std::string& prefix) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) return line;
    return "";
}

// Calibrates one unit with the rig's null ageing at 4 mV/h over `setpoints` (comma-separated
// degC) on the bus at `port` and analyses the run; returns the text `gyrocal analyze` printed.
// `dir` (empty) gets the files.
std::string CalibrateAndAnalyzeAging(const std::string& dir, const std::string& setpoints, int port,
                                     std::string& run) {
    const std::string db = dir + "/run.db", out = dir + "/calibrate.out";
    // ~1 simulated hour (OneEffectRunArgs). Aging 4 mV/h is ~4 mV over the run, ~1.2 mV RMS
    // about its mean: ~3x the floor bound of the outcome (~0.35 mV for 10 s bins of this rig's
    // noise, analyze.hpp step 9), so a missed drift must show.
    launch::ChildProcess cal(
        Joined({{GYROCAL_CLI, "calibrate", "--setpoints-c", setpoints, "--effect", "aging=0.004"},
                OneEffectRunArgs("12", db, UdpmUrl(port), dir + "/logs")}),
        out, out);
    auto ended = cal.Wait(540s);
    EXPECT_TRUE(ended.has_value()) << launch::ReadLog(out);
    if (!ended) return "";
    EXPECT_EQ(ended->code, 0) << launch::ReadLog(out);
    const auto runs = Sql(db).Rows("SELECT run_id FROM runs WHERE run_id <> ''");
    EXPECT_EQ(runs.size(), 1u);
    if (runs.empty()) return "";
    run = runs[0][0];
    // The truth file says the effect was on and is outside the candidate list.
    const json truth = json::parse(launch::ReadLog(dir + "/logs/truth.json"));
    EXPECT_EQ(truth.at("effects").at("aging").at("value"), 0.004);
    EXPECT_EQ(truth.at("effects").at("aging").at("analysis"), "outside the list");

    launch::ChildProcess an({GYROCAL_CLI, "analyze", run, "--db", db}, dir + "/analyze.out",
                            dir + "/analyze.err");
    auto an_end = an.Wait(180s);
    EXPECT_TRUE(an_end.has_value());
    if (!an_end) return "";
    EXPECT_EQ(an_end->code, 0) << launch::ReadLog(dir + "/analyze.err");
    const std::string printed = launch::ReadLog(dir + "/analyze.out");
    std::printf("%s", printed.c_str());
    return printed;
}

// Down, up, down, up, down (as the analysis tests' runs): time and temperature are not one
// another's function, so a drift in time cannot hide in the temperature terms.
TEST(OutsideEffectEndToEnd, AgingGivesAnUnexplainedResidualNamingNoCandidate) {
    const std::string dir = FreshDir("gyrocal_outside");
    const std::string db = dir + "/run.db";
    std::string run;
    const std::string printed = CalibrateAndAnalyzeAging(dir, "-10,50,10,70,30", 8000, run);
    ASSERT_FALSE(run.empty());
    const std::string verdict = LineStartingWith(printed, "sensor S01: ");
    ASSERT_FALSE(verdict.empty()) << printed;
    EXPECT_EQ(verdict.find("sensor S01: missing effect (unexplained residual)"), 0u) << verdict;
    // No candidate named as a cause in the verdict, none stored as added, no extended coefficient
    // set. The headline may end with "; ambiguous: A vs B", candidates whose regressors are
    // collinear on this data and that were therefore NOT added (seed 12 here: "ambiguous:
    // temp_rate vs hysteresis", z2 61 and 82, neither added), or with "; not attributed: X (...)",
    // a candidate the verdict says it does NOT name (a warm-up at the end of its grid that the
    // drift predicts as well); neither clause names a cause. Nothing is added either way (below).
    const std::string cause = verdict.substr(
        0, std::min(verdict.find("; ambiguous:"), verdict.find("; not attributed:")));
    for (const char* c : {"temp_rate", "hysteresis", "temp_cubic", "temp_knot", "supply ",
                          "sf_asymmetry", "warmup"})
        EXPECT_EQ(cause.find(c), std::string::npos) << c << " in: " << verdict;
    EXPECT_EQ(verdict.find("missing effect: "), std::string::npos) << verdict;
    Sql sql(db);
    EXPECT_EQ(sql.Rows("SELECT added_json FROM analyses WHERE run_id='" + run + "'").at(0).at(0),
              "[]");
    EXPECT_EQ(
        sql.Int("SELECT count(*) FROM analyses WHERE run_id='" + run + "' AND added_json != '[]'"),
        0);
    // `gyrocal analyze` stored no extended set; the fitter's closed loop stored the run's final
    // set (every still sample, the declared terms only: nothing was added).
    ExpectOnlyTheDeclaredClosedLoopSet(sql, run);
    // The diagnostic that points to it: what the residual correlates with is time-shaped.
    const auto at = verdict.find("correlates with");
    ASSERT_NE(at, std::string::npos) << verdict;
    EXPECT_NE(verdict.substr(at).find("[time"), std::string::npos) << verdict;
}

// The same unit and effect over the monotonic "five" setpoints (-40, -10, 25, 55, 85 degC): time
// and temperature rise together, the quadratic in temperature absorbs most of the drift, and
// what is left near the start looks like a warm-up.
// Before the rules against time-shaped mimics this named warmup(320) (-2.53 mV, "explained");
// now the joint search (the candidates tested again with the drift accounted for) leaves a
// warm-up named only without it "not attributed". The truth is an ageing null and nothing else,
// so the verdict must name no
// candidate as the cause and say that something is left, traced to time: "unexplained residual"
// correlating with a time shape, or "ambiguous" between a candidate and a time shape (the joint
// search: a warm-up named only while the drift is not accounted for), with nothing stored as
// added and no extended set (the run's two analyses: `gyrocal analyze`'s and the closed loop's).
TEST(OutsideEffectEndToEnd, AgingOnAMonotonicProfileNamesNoCandidate) {
    const std::string dir = FreshDir("gyrocal_outside_five");
    std::string run;
    const std::string printed = CalibrateAndAnalyzeAging(dir, "-40,-10,25,55,85", 8001, run);
    ASSERT_FALSE(run.empty());
    const std::string verdict = LineStartingWith(printed, "sensor S01: ");
    ASSERT_FALSE(verdict.empty()) << printed;
    EXPECT_EQ(verdict.find("missing effect: "), std::string::npos) << verdict;
    // Every analysis of the run says so: `gyrocal analyze`'s and the fitter's closed loop's (the
    // run's final set, source closed-loop: the declared terms only). No extended set.
    Sql sql(dir + "/run.db");
    const auto rows =
        sql.Rows("SELECT outcome, added_json FROM analyses WHERE run_id='" + run + "'");
    EXPECT_EQ(rows.size(), 2u);
    for (const auto& row : rows) {
        EXPECT_TRUE(row.at(0) == "unexplained residual" || row.at(0) == "ambiguous") << row.at(0);
        EXPECT_EQ(row.at(1), "[]");
    }
    ExpectOnlyTheDeclaredClosedLoopSet(sql, run);
    // On this profile temperature follows time, so a cubic would lower the held-out error as a
    // proxy of the drift: the closed loop's set does not carry it for prediction, and says why
    // when the residual is traced to time (analysis::CarryForPrediction).
    const std::string closed_loop_json =
        sql.Rows(
               "SELECT result_json FROM analyses a JOIN coeff_sets c USING(coeff_row_id) WHERE "
               "a.run_id='" +
               run + "' AND c.source='closed-loop'")
            .at(0)
            .at(0);
    if (closed_loop_json.find("correlates with time") != std::string::npos)
        EXPECT_NE(closed_loop_json.find("dT^3 not carried for prediction: the residual follows"),
                  std::string::npos);
    // Traced to time: a time-shaped correlate, or a tie with a time shape.
    EXPECT_TRUE(verdict.find("correlates with time since start [time") != std::string::npos ||
                verdict.find("[time") != std::string::npos ||
                verdict.find(" vs time since start") != std::string::npos ||
                verdict.find(" vs slow transient") != std::string::npos)
        << verdict;
}

TEST(OutsideEffectEndToEnd, BadEffectIsRefusedBeforeAnyProcessStarts) {
    const std::string dir = FreshDir("gyrocal_outside_bad");
    for (const auto& [effect, named] : std::vector<std::pair<std::string, std::string>>{
             {"aging=1", "aging"},
             {"tilt_deg=120", "tilt_deg"},
             {"compressor_period_s=0", "compressor_period_s"},
             {"agin=0.001", "aging"}}) {
        const std::string out = dir + "/bad.out";
        launch::ChildProcess cal(
            {GYROCAL_CLI, "calibrate", "--sensors", "1", "--db", dir + "/bad.db", "--lcm-url",
             "udpm://239.255.76.67:8002?ttl=0", "--effect", effect},
            out, out);
        auto ended = cal.Wait(60s);
        ASSERT_TRUE(ended.has_value());
        EXPECT_NE(ended->code, 0) << effect;
        const std::string printed = launch::ReadLog(out);
        EXPECT_NE(printed.find(named), std::string::npos) << effect << ": " << printed;
        EXPECT_FALSE(std::filesystem::exists(dir + "/bad.db")) << "nothing started for " << effect;
    }
}

}  // namespace
}  // namespace gyrocal
