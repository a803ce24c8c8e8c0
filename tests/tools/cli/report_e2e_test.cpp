// The calibration report end to end: `gyrocal calibrate --limits` over real processes (UDP
// multicast TTL 0, port 7870; bad files on 7872, never reached), a unit that fails its limits by
// the rig's known truth, the exit code and `gyrocal show` saying so, `gyrocal report` writing the
// page, and the page opened in a real headless chromium: rendered without errors or network
// requests, with its figures laid out and the run's numbers as the database holds them. The
// screenshot is saved beside the test's files (and to $GYROCAL_REPORT_SCREENSHOT when set).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "lcmtypes/launch/child_process.hpp"
#include "producers/sim/config.hpp"
#include "producers/sim/unit_model.hpp"
#include "tests/tools/cli/e2e_support.hpp"
#include "tests/tools/cli/headless_chromium.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
namespace fs = std::filesystem;

const std::string kUrl = UdpmUrl(7870);
const std::string kUnusedUrl = UdpmUrl(7872);

std::vector<std::vector<std::string>> Rows(const std::string& db, const std::string& sql) {
    return Sql(db).Rows(sql);
}

// Runs the gyrocal CLI to completion (bounded); returns the exit code, output in `out`.
int Cli(const std::vector<std::string>& args, const fs::path& out, std::chrono::seconds limit) {
    std::vector<std::string> argv = {GYROCAL_CLI};
    argv.insert(argv.end(), args.begin(), args.end());
    launch::ChildProcess p(argv, out.string(), out.string());
    const auto end = p.Wait(limit);
    if (!end) throw std::runtime_error("gyrocal did not finish: " + launch::ReadLog(out.string()));
    return end->exited ? end->code : 128 + end->signal;
}

// The browser checks below can fail: on a page with a script error, a console message and an
// image to fetch, the events show each of them.
TEST(HeadlessBrowser, SeesScriptErrorsConsoleMessagesAndRequests) {
    const std::string chromium = testing::HeadlessChromium::Find();
    if (chromium.empty())
        GTEST_SKIP() << "chromium is not installed (Debian chromium; tools/run.sh installs it)";
    const fs::path dir = FreshDir("gyrocal_browser_probe");
    std::ofstream(dir / "bad.html")
        << "<!DOCTYPE html><html><body><p id=p>x</p><img src=\"missing.png\">"
           "<script>console.log('hello'); throw new Error('boom');</script></body></html>";
    int exceptions = 0, console = 0, image_requests = 0;
    {
        testing::HeadlessChromium browser(chromium, (dir / "profile").string(),
                                          (dir / "chromium.log").string());
        const std::string s = browser.Open("file://" + (dir / "bad.html").string(), 800, 60s);
        EXPECT_EQ(browser.Evaluate(s, "document.getElementById('p').textContent"), "x");
        for (const json& e : browser.events()) {
            const std::string method = e.value("method", "");
            exceptions += method == "Runtime.exceptionThrown";
            console += method == "Runtime.consoleAPICalled";
            if (method == "Network.requestWillBeSent")
                image_requests += e["params"]["request"]["url"].get<std::string>().find(
                                      "missing.png") != std::string::npos;
        }
    }
    EXPECT_EQ(exceptions, 1);
    EXPECT_EQ(console, 1);
    EXPECT_EQ(image_requests, 1);
    fs::remove_all(dir);
}

TEST(CalibrateLimits, ABadLimitsFileStopsEverythingBeforeItStarts) {
    const fs::path dir = FreshDir("gyrocal_limits_bad");
    const fs::path db = dir / "never.db";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"max_offset_change_dps": "5"})",
         "key 'max_offset_change_dps': expected a number >= 0, got string"},
        {R"({"min_turn": 6})", "unknown key 'min_turn'"},
        {R"({"min_plateaus": -5})", "key 'min_plateaus': -5 is not valid"},
        {"{\"min_turns\": 6,,}", "not valid JSON"},
    };
    for (const auto& [text, expected] : cases) {
        const fs::path file = dir / "limits.json";
        std::ofstream(file) << text;
        const int rc =
            Cli({"calibrate", "--limits", file.string(), "--db", db.string(), "--lcm-url",
                 kUnusedUrl, "--log-dir", (dir / "logs").string(), "--quiet"},
                dir / "out.txt", 60s);
        const std::string out = launch::ReadLog((dir / "out.txt").string());
        EXPECT_EQ(rc, 2) << out;
        EXPECT_NE(out.find("--limits"), std::string::npos) << out;
        EXPECT_NE(out.find(expected), std::string::npos) << out;
        EXPECT_FALSE(fs::exists(db)) << "nothing may start before the limits are valid";
        EXPECT_FALSE(fs::exists(dir / "logs"));
    }
    EXPECT_EQ(Cli({"calibrate", "--limits", (dir / "missing.json").string(), "--db", db.string()},
                  dir / "out.txt", 60s),
              2);
    EXPECT_NE(launch::ReadLog((dir / "out.txt").string()).find("missing.json: cannot be read"),
              std::string::npos);
    // A report directory that cannot be made is refused as early.
    std::ofstream(dir / "limits.json") << R"({"min_turns": 6})";
    EXPECT_EQ(Cli({"calibrate", "--limits", (dir / "limits.json").string(), "--report",
                   "/nonexistent_gyrocal/r", "--db", db.string(), "--lcm-url", kUnusedUrl,
                   "--log-dir", (dir / "logs").string()},
                  dir / "out.txt", 60s),
              2);
    EXPECT_NE(launch::ReadLog((dir / "out.txt").string()).find("--report"), std::string::npos);
    EXPECT_FALSE(fs::exists(db));
    // gyrocal report needs a run or --latest.
    EXPECT_EQ(Cli({"report", "--db", db.string()}, dir / "out.txt", 60s), 2);
    EXPECT_NE(launch::ReadLog((dir / "out.txt").string()).find("--latest"), std::string::npos);
    fs::remove_all(dir);
}

// [deg/s] the true offset change of a simulated unit over die temperatures lo..hi, over its true
// sensitivity at mid-range (what max_offset_change_dps measures on the fitted curves).
double TrueOffsetChangeDps(const sim::UnitTruth& u, double lo, double hi) {
    double min_v = INFINITY, max_v = -INFINITY;
    for (int i = 0; i <= 2000; ++i) {
        const double v = u.OffsetV(lo + (hi - lo) * i / 2000.0);
        min_v = std::min(min_v, v);
        max_v = std::max(max_v, v);
    }
    return (max_v - min_v) / u.SensitivityVPerDps(0.5 * (lo + hi));
}

TEST(CalibrateLimits, AFailingUnitGivesExitCodeFourAndAReportThatSaysSoInABrowser) {
    const fs::path dir = FreshDir("gyrocal_report_e2e");
    // GIVEN the rig's two units of seed 7 and a limit on the offset change between their true
    // values. The fitted change differs from the truth by the plateau means' errors (slow noise
    // 0.015 deg/s each, about 0.03 deg/s on a difference of two) and the spread of the plateau
    // temperatures around the setpoints (<0.1 degC at ~0.6 mV/degC: <0.01 deg/s); a margin of
    // 0.5 deg/s on each side is more than 10 of those.
    sim::RigConfig rig;
    rig.seed = 7;
    rig.num_units = 2;
    std::map<std::string, double> truth;
    for (int i = 0; i < 2; ++i) {
        const std::string id = "S0" + std::to_string(i + 1);
        truth[id] = TrueOffsetChangeDps(sim::DrawUnit(rig, i, id), -10.0, 60.0);
    }
    const double limit = 0.5 * (truth["S01"] + truth["S02"]);
    ASSERT_GT(std::abs(truth["S01"] - truth["S02"]), 1.0) << "seed 7 no longer gives units apart";
    const std::string failing = truth["S01"] > limit ? "S01" : "S02";
    const std::string passing = failing == "S01" ? "S02" : "S01";
    const fs::path limits = dir / "limits.json";
    // (No count limits: on a loaded machine a turn can be refused for lost samples, and the unit
    // would then fail for that, rightly; the counts are tested on stored data in runreport_tests.)
    std::ofstream(limits) << json{
        {"description", "e2e"},
        {"max_offset_change_dps", limit},
        {"max_sensitivity_rel_uncertainty_pct",
         1.0}}.dump();

    // WHEN the seed's 3-point procedure runs with those limits (fast thermal constants as in
    // calibrate_e2e_test.cpp)
    const std::string db = (dir / "run.db").string();
    const int rc = Cli(Joined({{"calibrate", "--profile", "seed3"},
                               SimRunArgs("2", "7", "40", db, kUrl, (dir / "logs").string()),
                               kFastThermalArgs,
                               {"--wall-timeout-s", "400", "--limits", limits.string(), "--report",
                                (dir / "calibrate-report").string()}}),
                       dir / "calibrate.out", 450s);
    const std::string printed = launch::ReadLog((dir / "calibrate.out").string());

    // THEN the exit code says a unit did not pass, and the failing unit and limit are named
    ASSERT_EQ(rc, 4) << printed;
    EXPECT_NE(printed.find("stop: completed"), std::string::npos) << printed;
    EXPECT_NE(
        printed.find("unit did not pass its limits: " + failing + ": FAIL: max_offset_change_dps"),
        std::string::npos)
        << printed;
    EXPECT_EQ(printed.find("unit did not pass its limits: " + passing), std::string::npos)
        << printed;
    EXPECT_NE(printed.find("  " + passing + ": pass"), std::string::npos) << printed;
    const std::string run = Rows(db, "SELECT run_id FROM runs WHERE run_id <> ''").at(0).at(0);
    // --report: the page of this run, written at the end, its path printed.
    const fs::path written = dir / "calibrate-report" / ("report-" + run + ".html");
    EXPECT_NE(printed.find("report: " + written.string()), std::string::npos) << printed;
    EXPECT_TRUE(fs::exists(written));
    // The limits are stored with the run.
    const json config =
        json::parse(Rows(db, "SELECT config_json FROM runs WHERE run_id <> ''").at(0).at(0));
    EXPECT_DOUBLE_EQ(config.at("acceptance_limits").at("max_offset_change_dps").get<double>(),
                     limit);

    // AND gyrocal show prints the outcome per unit
    ASSERT_EQ(Cli({"show", run, "--db", db}, dir / "show.out", 60s), 0);
    const std::string shown = launch::ReadLog((dir / "show.out").string());
    EXPECT_NE(shown.find("Acceptance (limits stored with run " + run), std::string::npos) << shown;
    EXPECT_NE(shown.find("  " + failing + ": FAIL: max_offset_change_dps"), std::string::npos)
        << shown;
    EXPECT_NE(shown.find("  " + passing + ": pass"), std::string::npos) << shown;

    // AND gyrocal report writes the page
    ASSERT_EQ(Cli({"report", run, "--db", db, "--out", (dir / "report").string()},
                  dir / "report.out", 120s),
              0)
        << launch::ReadLog((dir / "report.out").string());
    const fs::path page = dir / "report" / ("report-" + run + ".html");
    EXPECT_NE(launch::ReadLog((dir / "report.out").string()).find("report: " + page.string()),
              std::string::npos);
    ASSERT_TRUE(fs::exists(page));

    // AND a real browser renders it without errors and without any request but the file
    const std::string chromium = testing::HeadlessChromium::Find();
    if (chromium.empty())
        GTEST_SKIP() << "chromium is not installed (Debian chromium; tools/run.sh installs it)";
    std::optional<testing::HeadlessChromium> chrome;
    chrome.emplace(chromium, (dir / "chromium-profile").string(), (dir / "chromium.log").string());
    testing::HeadlessChromium& browser = *chrome;
    const std::string url = "file://" + page.string();
    const std::string s = browser.Open(url, 1200, 120s);
    const json dom = json::parse(browser
                                     .Evaluate(s, R"js(JSON.stringify({
        runId: document.querySelector('[data-run-id]').textContent,
        figures: [...document.querySelectorAll('svg.figure')].map(f => {
            const r = f.getBoundingClientRect();
            return {name: f.dataset.figure, w: r.width, h: r.height, marks: f.querySelectorAll('path, use').length};
        }),
        units: [...document.querySelectorAll('section.unit')].map(u => ({
            sensor: u.dataset.sensor,
            offset: [...u.querySelector('[data-part=coefficients] div[data-coeff-row]')
                         .querySelectorAll('tr[data-quantity=offset_v]')].map(tr => [tr.dataset.term, tr.cells[1].textContent]),
            plateaus: u.querySelectorAll('table.plateaus tbody tr').length,
            turns: u.querySelectorAll('table.turns tbody tr').length,
            notMeasured: u.querySelectorAll('p.not-measured').length})),
        acceptance: [...document.querySelectorAll('table.acceptance-summary tbody tr')].map(tr => ({
            sensor: tr.dataset.sensor, outcome: tr.dataset.outcome,
            change: tr.querySelector('td[data-key=max_offset_change_dps]').textContent}))
    }))js")
                                     .get<std::string>());
    int requests = 0;
    for (const json& e : browser.events()) {
        const std::string method = e.value("method", "");
        EXPECT_NE(method, "Runtime.exceptionThrown") << e.dump();
        EXPECT_NE(method, "Runtime.consoleAPICalled") << e.dump();
        if (method == "Log.entryAdded") {
            const std::string level = e["params"]["entry"].value("level", "");
            EXPECT_TRUE(level != "error" && level != "warning") << e.dump();
        }
        if (method == "Network.requestWillBeSent") {
            ++requests;
            EXPECT_EQ(e["params"]["request"]["url"], url) << e.dump();
        }
    }
    EXPECT_EQ(requests, 1) << "the page itself, nothing else";
    EXPECT_EQ(dom["runId"], run);

    // The figures are laid out (two per row on a 1200 px page) and drawn: offset, sensitivity and
    // three residual figures per unit.
    ASSERT_EQ(dom["figures"].size(), 10u) << dom.dump(2);
    for (const json& f : dom["figures"]) {
        EXPECT_GT(f["w"].get<double>(), 300) << f.dump();
        EXPECT_GT(f["h"].get<double>(), 150) << f.dump();
        EXPECT_GT(f["marks"].get<int>(), 10) << f.dump();
    }
    // The tables carry the database's numbers: the calibration's offset coefficients (printed
    // with 6 significant digits: relative rounding below 5e-6), every plateau and turn.
    ASSERT_EQ(dom["units"].size(), 2u);
    for (const json& u : dom["units"]) {
        const std::string id = u["sensor"];
        SCOPED_TRACE(id);
        const auto coeffs =
            Rows(db,
                 "SELECT t.term_name, t.coeff FROM coeff_terms t WHERE t.role = 'offset' AND "
                 "t.coeff_row_id = (SELECT max(coeff_row_id) FROM coeff_sets WHERE sensor_id = '" +
                     id + "' AND source = 'fitter') ORDER BY t.term_index");
        ASSERT_EQ(u["offset"].size(), coeffs.size());
        for (size_t i = 0; i < coeffs.size(); ++i) {
            EXPECT_EQ(u["offset"][i][0], coeffs[i][0]);
            const double stored = std::stod(coeffs[i][1]);
            EXPECT_NEAR(std::stod(u["offset"][i][1].get<std::string>()), stored,
                        5e-6 * std::abs(stored))
                << coeffs[i][0];
        }
        EXPECT_EQ(u["plateaus"],
                  std::stoi(Rows(
                      db, "SELECT count(*) FROM plateaus WHERE sensor_id='" + id + "'")[0][0]));
        EXPECT_EQ(u["turns"],
                  std::stoi(Rows(db, "SELECT count(*) FROM sensitivity_points WHERE sensor_id='" +
                                         id + "'")[0][0]));
        // Allan deviation, repeatability, validation and the analysis: one line each.
        EXPECT_EQ(u["notMeasured"], 4);
    }
    // The acceptance table says which unit failed, with the change the truth predicts.
    ASSERT_EQ(dom["acceptance"].size(), 2u);
    for (const json& a : dom["acceptance"]) {
        const std::string id = a["sensor"];
        EXPECT_EQ(a["outcome"], id == failing ? "FAIL" : "pass") << a.dump();
        EXPECT_NEAR(std::stod(a["change"].get<std::string>()), truth[id], 0.1) << a.dump();
    }

    // AND a screenshot of the whole page is saved
    const std::string png = browser.Screenshot(s);
    ASSERT_GT(png.size(), 50000u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    std::ofstream(dir / "report.png", std::ios::binary) << png;
    if (const char* copy = std::getenv("GYROCAL_REPORT_SCREENSHOT"))
        std::ofstream(copy, std::ios::binary) << png;
    // The page and its screenshot stay with the test's files; the database and profile go.
    chrome.reset();
    if (!HasFailure()) {
        fs::remove_all(dir / "chromium-profile");
        fs::remove_all(dir / "logs");
        for (const char* f : {"run.db", "run.db-wal", "run.db-shm"}) fs::remove(dir / f);
    }
}

}  // namespace
}  // namespace gyrocal
