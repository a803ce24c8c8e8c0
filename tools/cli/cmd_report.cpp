#include "tools/cli/cmd_report.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "gyrocal/version.hpp"
#include "processors/acceptance/limits.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"
#include "store/db/query.hpp"
#include "store/runreport/build.hpp"
#include "store/runreport/unit_data.hpp"
#include "tools/cli/cmd_analyze.hpp"
#include "tools/cli/command.hpp"

namespace gyrocal::cli {

namespace fs = std::filesystem;
namespace rr = gyrocal::runreport;
namespace st = gyrocal::db;
using supervisor::CalibrateOptions;

namespace {

// The newest run of the database (gyrocal runs lists it first); throws NotFound when none.
std::string LatestRun(const std::string& db_path) {
    auto db = st::OpenForQuery(db_path);
    for (const st::RunInfo& r : st::ListRuns(*db, {}))
        if (!r.run_id.empty()) return r.run_id;
    throw st::NotFound("no run in database '" + db->path() + "'");
}

// "" when DIR can hold the report (created when its parent exists); else what is wrong.
std::string PrepareOutDir(const std::string& out_dir) {
    fs::path dir = fs::absolute(out_dir).lexically_normal();
    if (!dir.has_filename()) dir = dir.parent_path();
    std::error_code ec;
    if (fs::exists(dir, ec))
        return fs::is_directory(dir, ec) ? ""
                                         : "--out " + out_dir + ": exists and is not a directory";
    if (!fs::is_directory(dir.parent_path(), ec))
        return "--out " + out_dir + ": parent directory '" + dir.parent_path().string() +
               "' does not exist (DIR itself is created, its parent must exist)";
    fs::create_directory(dir, ec);
    return ec ? "--out " + out_dir + ": " + ec.message() : "";
}

}  // namespace

int RunReport(const ReportCommandOptions& o, std::ostream& out, std::ostream& err) {
    rr::ReportOptions ro;
    if (!o.limits_file.empty()) {
        try {
            ro.limits = acceptance::LoadLimitsFile(o.limits_file);
            ro.limits_origin =
                "from " + o.limits_file + " (given to gyrocal report, not stored with the run)";
        } catch (const acceptance::LimitsError& e) {
            err << "gyrocal report: --limits: " << e.what() << "\n";
            return 2;
        }
    }
    if (const std::string p = PrepareOutDir(o.out_dir); !p.empty()) {
        err << "gyrocal report: " << p << "\n";
        return 2;
    }
    ro.gnuplot = plot::gnuplot::FindOnPath("gnuplot");
    if (ro.gnuplot.empty()) {
        err << "gyrocal report: " << plot::gnuplot::kGnuplotMissing << "\n";
        return 1;
    }
    return FailOnThrow(err, "gyrocal report: ", [&] {
        ro.db = o.db;
        ro.run_id = o.latest ? LatestRun(o.db) : o.run_id;
        ro.out_dir = o.out_dir;
        ro.software_version = kSoftwareVersion;
        const rr::ReportResult r = rr::WriteReport(ro);
        if (o.json) {
            nlohmann::json j = rr::AcceptanceJson(r.acceptance);
            j["report"] = r.path;
            j["run_id"] = ro.run_id;
            j["figures"] = r.figures;
            out << j.dump(2) << "\n";
        } else {
            out << "report: " << r.path << "\n" << rr::AcceptanceText(r.acceptance);
        }
        return out ? 0 : 1;
    });
}

void AddReportCommand(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<ReportCommandOptions>();
    CLI::App* sub = app.add_subcommand(
        "report",
        "the calibration report of a run: one self-contained HTML page (figures, coefficients with "
        "uncertainties, analysis, acceptance, traceability)");
    sub->option_defaults()->always_capture_default();  // --help shows every option's default
    auto* run = sub->add_option("run", o->run_id, "run id (see gyrocal runs)");
    auto* latest = sub->add_flag("--latest", o->latest, "the newest run of the database");
    run->excludes(latest);
    sub->add_option("--db", o->db, "SQLite database the recorder wrote");
    sub->add_option("--out", o->out_dir,
                    "directory of the page report-<run>.html (created if its parent exists)");
    sub->add_option(
        "--limits", o->limits_file,
        "acceptance limits (JSON) to judge the run by, instead of those stored with it");
    sub->add_flag("--json", o->json, "print the path and the acceptance as JSON");
    sub->footer(
        "Exit codes: 0 report written (whatever the units' outcome), 1 failure (database, unknown "
        "run, gnuplot "
        "missing or failing, page not writable), 2 bad options (incl. a limits file that does not "
        "validate).");
    sub->callback([o, &action] {
        if (o->run_id.empty() && !o->latest) throw CLI::RequiredError("a RUN id or --latest");
        action = [o] { return RunReport(*o, std::cout, std::cerr); };
    });
}

namespace {

// The acceptance of the run just made: analysed first when a limit needs it, judged, each unit
// that did not pass named; returns the exit code.
int AcceptanceStep(const CalibrateOptions& options, const std::string& run_id, int code) {
    try {
        const acceptance::Limits limits =
            acceptance::FromJson(nlohmann::json::parse(options.limits_json), options.limits_file);
        if (limits.no_unexplained_residual) {
            // The analysis is this limit's evidence; it is stored with the run like any other.
            AnalyzeOptions ao;
            ao.run_id = run_id;
            ao.db = options.db;
            ao.command_line = "gyrocal calibrate --limits " + options.limits_file +
                              " (analysis of run " + run_id + ")";
            std::ostringstream report;
            if (RunAnalyze(ao, report, std::cerr) != 0)
                std::cerr << "gyrocal calibrate: the analysis of run " << run_id
                          << " failed; no_unexplained_residual stays not evaluated\n";
        }
        auto db = st::OpenForQuery(options.db);
        const st::RunDetail detail = st::ShowRun(*db, run_id);
        const rr::RunAcceptance a = rr::AcceptRun(detail, limits, "from " + options.limits_file);
        std::cout << "\n" << rr::AcceptanceText(a);
        bool all_pass = !a.verdicts.empty();
        for (const acceptance::UnitVerdict& v : a.verdicts) {
            if (v.outcome == acceptance::Outcome::kPass) continue;
            all_pass = false;
            std::cerr << "gyrocal calibrate: unit did not pass its limits: "
                      << acceptance::Summary(v) << "\n";
        }
        return code == 0 && !all_pass ? kExitUnitNotAccepted : code;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: acceptance of run " << run_id
                  << " not evaluated: " << e.what() << "\n";
        return code == 0 ? kExitUnitNotAccepted : code;
    }
}

// The report of the run just made (whatever its outcome); a report that cannot be written fails
// a run that had succeeded.
int ReportStep(const CalibrateOptions& options, const std::string& run_id, int code) {
    if (const std::string p = PrepareOutDir(options.report_dir); !p.empty()) {
        std::cerr << "gyrocal calibrate: " << p << "\n";
        return code == 0 ? 1 : code;
    }
    try {
        rr::ReportOptions ro;
        ro.db = options.db;
        ro.run_id = run_id;
        ro.out_dir = options.report_dir;
        ro.gnuplot = plot::gnuplot::FindOnPath("gnuplot");
        ro.software_version = kSoftwareVersion;
        if (ro.gnuplot.empty()) throw std::runtime_error(plot::gnuplot::kGnuplotMissing);
        std::cout << "\nreport: " << rr::WriteReport(ro).path << "\n";
        return code;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: the report of run " << run_id
                  << " was not written: " << e.what() << "\n";
        return code == 0 ? 1 : code;
    }
}

}  // namespace

int AfterCalibration(const CalibrateOptions& options, const std::string& run_id, int code) {
    if (!options.limits_json.empty()) code = AcceptanceStep(options, run_id, code);
    if (!options.report_dir.empty()) code = ReportStep(options, run_id, code);
    return code;
}

}  // namespace gyrocal::cli
