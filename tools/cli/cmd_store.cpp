// `gyrocal runs|show|history|export|fleet|replay`: thin CLI over the query library (store/db) and
// the formatters (store/format). Errors are one line on stderr naming the command.
#include "tools/cli/cmd_store.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"
#include "store/db/central_url.hpp"
#include "store/db/query.hpp"
#include "store/format/fleet.hpp"
#include "store/format/format.hpp"
#include "store/format/samples_csv.hpp"
#include "store/runreport/unit_data.hpp"

namespace {

namespace st = gyrocal::db;
namespace rep = gyrocal::format;

constexpr const char* kExitCodes =
    "Exit codes: 0 success, 1 unknown run/sensor or database/output failure, 2 bad options.";

// Runs `body`, turning the library's exceptions into one line on stderr and exit code 1.
int Guarded(const std::string& command, const std::function<int()>& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        std::cerr << "gyrocal " << command << ": error: " << rep::Printable(e.what()) << "\n";
        return 1;
    }
}

// Writes to --out FILE (when given) or stdout.
int Emit(const std::string& command, const std::string& text, const std::string& out_path) {
    if (out_path.empty()) {
        std::cout << text;
        std::cout.flush();
        return std::cout ? 0 : 1;
    }
    std::ofstream f(out_path, std::ios::binary | std::ios::trunc);
    if (f) f << text;
    if (f) f.close();
    if (!f) {
        std::cerr << "gyrocal " << command << ": error: --out: cannot write '" << out_path << "'\n";
        return 1;
    }
    return 0;
}

CLI::Validator UtcDate() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            return rep::ParseUtc(s) ? ""
                                    : "'" + s +
                                          "' is not a UTC date (YYYY-MM-DD or "
                                          "YYYY-MM-DDTHH:MM[:SS][Z])";
        },
        "DATE");
}

// A list of temperatures [degC] (rep::ParseTemps).
CLI::Validator TempList() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            return rep::ParseTemps(s) ? "" : "'" + s + "' is not a list of numbers like 0,25,50";
        },
        "LIST");
}

// What every store command has; each command adds its own values in a struct of its own, held by
// one shared object that its options set at the parse and its action reads after it.
struct Common {
    std::string db = "gyrocal.db";
    bool json = false;
};

void AddDb(CLI::App* sub, Common& c) {
    sub->add_option("--db", c.db,
                    "SQLite database the recorder wrote, or the lab's central database "
                    "(postgresql://[user@]host[:port]/db)")
        ->capture_default_str();
}

std::vector<rep::ProvenanceSummary> Provenance(st::Db& db,
                                               const std::vector<st::CoeffSetInfo>& sets) {
    std::vector<rep::ProvenanceSummary> out;
    for (const auto& c : sets)
        out.push_back({c.coeff_row_id, st::CoeffProvenance(db, c.coeff_row_id)});
    return out;
}

struct RunsCli : Common {
    std::string sensor;
    std::string since;
    std::string until;
    std::string outcome;
};

void AddRuns(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<RunsCli>();
    CLI::App* sub = app.add_subcommand("runs", "list recorded runs, newest first");
    sub->footer(kExitCodes);
    AddDb(sub, *c);
    sub->add_option("--sensor", c->sensor, "only runs that recorded this sensor id");
    sub->add_option("--since", c->since, "only runs first seen at/after this UTC date")
        ->check(UtcDate());
    sub->add_option("--until", c->until, "only runs first seen before this UTC date")
        ->check(UtcDate());
    sub->add_option("--outcome", c->outcome, "only runs that ended so")
        ->check(CLI::IsMember({"running", "stop", "abort", "none"}));
    sub->add_flag("--json", c->json, "JSON array instead of a table");
    sub->callback([&action, c, sub] {
        action = [c, sub] {
            return Guarded("runs", [&] {
                st::RunFilter f;
                if (sub->count("--sensor")) f.sensor_id = c->sensor;
                if (!c->since.empty()) f.since_utime = rep::ParseUtc(c->since);
                if (!c->until.empty()) f.until_utime = rep::ParseUtc(c->until);
                if (!c->outcome.empty()) f.outcome = c->outcome;
                auto db = st::OpenForQuery(c->db);
                const auto runs = st::ListRuns(*db, f);
                if (c->json) return Emit("runs", rep::RunsJson(runs).dump(2) + "\n", "");
                if (runs.empty()) {
                    std::cout << "no runs match in "
                              << rep::Printable(st::WithoutCredentials(c->db)) << "\n";
                    return 0;
                }
                return Emit("runs", rep::RunsTable(runs), "");
            });
        };
    });
}

struct ShowCli : Common {
    std::string run;
};

void AddShow(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<ShowCli>();
    CLI::App* sub = app.add_subcommand("show",
                                       "a run: configuration, plateaus, sensitivity points, "
                                       "coefficient sets, analyses, losses, acceptance");
    sub->footer(kExitCodes);
    sub->add_option("run", c->run, "run id ('' = the no-run bucket)")->required();
    AddDb(sub, *c);
    sub->add_flag("--json", c->json, "JSON instead of text");
    sub->callback([&action, c] {
        action = [c] {
            return Guarded("show", [&] {
                auto db = st::OpenForQuery(c->db);
                const st::RunDetail d = st::ShowRun(*db, c->run);
                const auto prov = Provenance(*db, d.coeff_sets);
                // The outcome per unit against the limits stored with the run.
                const auto accepted = gyrocal::runreport::AcceptRun(d);
                if (c->json) {
                    nlohmann::json j = rep::RunDetailJson(d, prov);
                    j["acceptance"] = gyrocal::runreport::AcceptanceJson(accepted);
                    return Emit("show", j.dump(2) + "\n", "");
                }
                return Emit("show",
                            rep::RunDetailText(d, prov) + "\n" +
                                gyrocal::runreport::AcceptanceText(accepted),
                            "");
            });
        };
    });
}

struct HistoryCli : Common {
    std::string sensor;
    std::string temps = "0,25,50";
    bool all = false;
};

void AddHistory(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<HistoryCli>();
    CLI::App* sub = app.add_subcommand(
        "history", "every coefficient set of a sensor and how offset and sensitivity moved");
    sub->footer(kExitCodes);
    sub->add_option("sensor", c->sensor, "sensor id")->required();
    AddDb(sub, *c);
    sub->add_option("--ref-temps-c", c->temps, "reference temperatures [degC], comma separated")
        ->capture_default_str()
        ->check(TempList());
    sub->add_flag(
        "--all", c->all,
        "every coefficient set published (default: the final one of each run and source)");
    sub->add_flag("--json", c->json, "JSON instead of a table");
    sub->callback([&action, c] {
        action = [c] {
            return Guarded("history", [&] {
                const std::vector<double> ref = *rep::ParseTemps(c->temps);
                auto db = st::OpenForQuery(c->db);
                const auto sets = st::SensorHistory(*db, c->sensor, !c->all);
                if (c->json) {
                    return Emit("history", rep::HistoryJson(c->sensor, sets, ref).dump(2) + "\n",
                                "");
                }
                return Emit("history", rep::HistoryTable(c->sensor, sets, ref), "");
            });
        };
    });
}

// A run's raw samples as CSV, streamed (a run holds millions of samples).
int ExportSamples(st::Db& db, const std::string& run_id, const std::string& sensor,
                  const std::string& out_path) {
    std::ofstream file;
    if (!out_path.empty()) file.open(out_path, std::ios::binary | std::ios::trunc);
    std::ostream& out = out_path.empty() ? std::cout : file;
    if (!out) throw std::runtime_error("--out: cannot write '" + out_path + "'");
    const int64_t rows = rep::WriteRunSamplesCsv(db, run_id, sensor, out);
    out.flush();
    if (!out) throw std::runtime_error("--out: cannot write '" + out_path + "'");
    if (rows == 0)
        throw st::NotFound("run '" + run_id + "' has no samples" +
                           (sensor.empty() ? std::string() : " of sensor '" + sensor + "'"));
    std::cerr << "gyrocal export: " << rows << " samples\n";
    return 0;
}

struct ExportCli : Common {
    std::string id;
    std::string format = "json";
    std::string out;
    std::string kind = "auto";
    std::string sensor;
};

void AddExport(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<ExportCli>();
    CLI::App* sub = app.add_subcommand(
        "export",
        "coefficients of a run (newest set of each sensor, whatever its source: an analysis'\n"
        "extended model stored after the fitter's set wins) or of a sensor (its newest set);\n"
        "--format samples: the run's raw samples as measured-data CSV (gyrocal compensate reads "
        "it)");
    sub->footer(kExitCodes);
    sub->add_option("id", c->id, "run id or sensor id (a run id wins; see --kind)")->required();
    AddDb(sub, *c);
    sub->add_option("--format", c->format, "json, csv, c-header, or samples (a run's raw samples)")
        ->check(CLI::IsMember({"json", "csv", "c-header", "samples"}))
        ->capture_default_str();
    sub->add_option("--sensor", c->sensor, "with --format samples: only this sensor");
    sub->add_option("--out", c->out, "write to this file instead of stdout");
    sub->add_option("--kind", c->kind, "what id names: auto, run or sensor")
        ->check(CLI::IsMember({"auto", "run", "sensor"}))
        ->capture_default_str();
    sub->callback([&action, c] {
        action = [c] {
            return Guarded("export", [&] {
                auto db = st::OpenForQuery(c->db);
                if (c->format == "samples") return ExportSamples(*db, c->id, c->sensor, c->out);
                const bool is_run =
                    c->kind == "run" || (c->kind == "auto" && st::RunExists(*db, c->id));
                std::vector<st::CoeffSetInfo> sets;
                std::string origin;
                if (is_run) {
                    sets = st::RunNewestCoeffs(*db, c->id);
                    origin = "run '" + c->id + "' of " + st::WithoutCredentials(c->db);
                } else {
                    if (c->kind == "auto" && !st::SensorExists(*db, c->id)) {
                        throw st::NotFound("'" + c->id + "' is neither a run nor a sensor in '" +
                                           st::WithoutCredentials(c->db) + "' (see gyrocal runs)");
                    }
                    auto all = st::SensorHistory(*db, c->id, true);
                    if (!all.empty()) sets.push_back(all.back());
                    origin =
                        "sensor '" + c->id + "' (newest set) of " + st::WithoutCredentials(c->db);
                }
                if (sets.empty()) {
                    throw st::NotFound(std::string(is_run ? "run '" : "sensor '") + c->id +
                                       "' has no coefficient sets");
                }
                std::string text;
                if (c->format == "csv") {
                    text = rep::CoeffsCsv(sets);
                } else if (c->format == "c-header") {
                    text = rep::CoeffsCHeader(sets, origin);
                } else {
                    nlohmann::json j;
                    j["exported_from"] = origin;
                    j["coeff_sets"] = nlohmann::json::array();
                    for (const auto& s : sets) j["coeff_sets"].push_back(rep::CoeffSetJson(s));
                    text = j.dump(2) + "\n";
                }
                return Emit("export", text, c->out);
            });
        };
    });
}

// The units of the fleet view: each sensor's newest set, its run's model and station.
std::vector<rep::FleetUnit> FleetUnits(st::Db& db, const std::string& model) {
    std::map<std::string, std::string> configs;
    for (const st::RunInfo& r : st::ListRuns(db, {})) configs[r.run_id] = r.config_json;
    std::vector<rep::FleetUnit> units;
    for (st::CoeffSetInfo& c : st::NewestSetOfEachSensor(db)) {
        rep::FleetUnit u{c.set.sensor_id, rep::UnitModelOf(configs[c.set.run_id], c.set.sensor_id),
                         c.station,       c.set.run_id,
                         c.coeff_row_id,  std::move(c.set)};
        if (model.empty() || u.model == model) units.push_back(std::move(u));
    }
    return units;
}

int DrawFleet(const std::vector<rep::FleetGroup>& groups, const rep::FleetOptions& o,
              const std::string& dir) {
    const std::string gnuplot = gyrocal::plot::gnuplot::FindOnPath("gnuplot");
    if (gnuplot.empty())
        throw std::runtime_error(std::string("--plot ") + gyrocal::plot::gnuplot::kGnuplotMissing);
    std::error_code ec;
    std::filesystem::create_directory(dir, ec);
    if (ec) throw std::runtime_error("--plot " + dir + ": " + ec.message());
    const auto images = gyrocal::plot::gnuplot::DrawInto(
        gnuplot, dir, rep::FleetFigures(groups, o),
        {gyrocal::plot::Terminal::kPng, gyrocal::plot::Terminal::kSvg});
    std::cerr << "gyrocal fleet: wrote " << images.size() << " pictures to " << dir << "\n";
    return 0;
}

struct FleetCli : Common {
    rep::FleetOptions o;
    std::string model;
    std::string temps;
    std::string plot_dir;
};

void AddFleet(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<FleetCli>();
    CLI::App* sub = app.add_subcommand(
        "fleet",
        "per unit model: the spread of the units' offset and sensitivity curves across units and\n"
        "stations (median and 1.4826 MAD at each temperature), the units outside it, and each\n"
        "station's median deviation; best on the lab's central database");
    sub->footer(
        "Exit codes: 0 success (whatever the units' deviations), 1 database or plot "
        "failure, 2 bad options.");
    AddDb(sub, *c);
    sub->add_option("--model", c->model, "only this unit model (as `gyrocal fleet` names it)");
    sub->add_option("--temps-c", c->temps,
                    "temperature grid [degC], comma separated "
                    "(default -40 to 85 in steps of 5)")
        ->check(TempList());
    sub->add_option("--k", c->o.k, "a unit is outside when |z| > K")
        ->check(CLI::Range(0.5, 100.0))
        ->capture_default_str();
    sub->add_option("--min-units", c->o.min_units, "units needed at a temperature for a spread")
        ->check(CLI::Range(3, 100000))
        ->capture_default_str();
    sub->add_option("--plot", c->plot_dir, "directory for the pictures (PNG + SVG, gnuplot)");
    sub->add_flag("--json", c->json, "JSON instead of tables");
    sub->callback([&action, c] {
        action = [c] {
            return Guarded("fleet", [&] {
                if (!c->temps.empty()) c->o.temps_c = *rep::ParseTemps(c->temps);
                auto db = st::OpenForQuery(c->db);
                const auto groups = rep::FleetSpread(FleetUnits(*db, c->model), c->o);
                if (groups.empty())
                    throw st::NotFound("no unit " +
                                       (c->model.empty() ? "" : "of model '" + c->model + "' ") +
                                       "has a coefficient set in '" + db->path() + "'");
                if (!c->plot_dir.empty()) DrawFleet(groups, c->o, c->plot_dir);
                if (c->json) return Emit("fleet", rep::FleetJson(groups, c->o).dump(2) + "\n", "");
                return Emit("fleet", rep::FleetText(groups, c->o), "");
            });
        };
    });
}

struct ReplayCli : Common {
    std::string run;
    double speed = 1.0;
    bool max = false;
    std::string url;
    std::string as_run;
};

void AddReplay(CLI::App& app, std::function<int()>& action) {
    auto c = std::make_shared<ReplayCli>();
    CLI::App* sub = app.add_subcommand(
        "replay", "publish a stored run back onto LCM with its original timing (gyrocal-replay)");
    sub->footer(kExitCodes);
    sub->add_option("run", c->run, "run id")->required();
    AddDb(sub, *c);
    gyrocal::process::AddPacingOptions(*sub, c->speed, c->max, "recorded seconds per wall second")
        ->check(CLI::Range(1e-3, 1e6))
        ->capture_default_str();
    sub->add_option("--lcm-url", c->url, "LCM URL (default $GYROCAL_LCM_URL or udpm default)");
    sub->add_option("--as-run", c->as_run, "publish the run events under this run id instead");
    sub->callback([&action, c, sub] {
        action = [c, sub] {
            const std::string exe = gyrocal::process::ExecutableDir() + "/gyrocal-replay";
            std::vector<std::string> args = {exe, c->run, "--db", c->db};
            if (c->max) {
                args.push_back("--max");
            } else if (sub->count("--speed")) {
                args.push_back("--speed");
                args.push_back(std::to_string(c->speed));
            }
            if (!c->as_run.empty()) {
                args.push_back("--as-run");
                args.push_back(c->as_run);
            }
            if (!c->url.empty()) {
                args.push_back("--lcm-url");
                args.push_back(c->url);
            }
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(exe.c_str(), argv.data());
            std::cerr << "gyrocal replay: error: cannot start '" << exe
                      << "' (build it beside gyrocal)\n";
            return 1;
        };
    });
}

}  // namespace

void AddStoreCommands(CLI::App& app, std::function<int()>& action) {
    AddRuns(app, action);
    AddShow(app, action);
    AddHistory(app, action);
    AddExport(app, action);
    AddFleet(app, action);
    AddReplay(app, action);
}
