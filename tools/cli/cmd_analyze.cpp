#include "tools/cli/cmd_analyze.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <variant>
#include <vector>

#include "gyrocal/version.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/text/number.hpp"
#include "processors/analysis/analyze.hpp"
#include "processors/analysis/plot.hpp"
#include "processors/analysis/report.hpp"
#include "processors/analysis/run_data.hpp"
#include "processors/noise/allan_plot.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/query.hpp"
#include "tools/cli/command.hpp"
#include "tools/cli/run_loader.hpp"

namespace gyrocal::cli {

namespace an = gyrocal::analysis;
namespace st = gyrocal::db;

namespace {

namespace fs = std::filesystem;

// The unit's Allan deviation from the run's newest NOISE_<id> record, when one was recorded.
void AddAllanPlot(const st::RunDetail& d, const std::string& id, std::vector<plot::Figure>& plots) {
    for (const st::NoiseInfo& ni : d.noise) {
        if (ni.noise.sensor_id != id || ni.noise.tau_s.empty()) continue;
        const st::NoiseRow& n = ni.noise;
        plots.push_back(
            noise::MakeAllanPlot({id, n.tau_s, n.adev_v, n.adev_lo_v, n.adev_hi_v, n.arw_v_rthz,
                                  n.bias_instability_v, n.rrw_v_rts, ni.sensitivity_v_per_dps}));
    }
}

// Checks --plot DIR before the (long) analysis so that a wrong DIR costs nothing, and finds
// gnuplot into `gnuplot`. Returns the exit code when the command must end now.
std::optional<int> CheckPlotDir(const AnalyzeOptions& o, std::string& gnuplot, std::ostream& err) {
    fs::path dir = fs::absolute(o.plot_dir).lexically_normal();
    if (!dir.has_filename()) dir = dir.parent_path();  // "pics/" -> "pics"
    const fs::path parent = dir.parent_path();
    std::error_code ec;
    if (!fs::is_directory(parent, ec)) {
        err << "gyrocal analyze: --plot " << o.plot_dir << ": parent directory '" << parent.string()
            << "' does not exist (DIR itself is created, its parent must exist)\n";
        return 2;
    }
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
        err << "gyrocal analyze: --plot " << o.plot_dir << ": exists and is not a directory\n";
        return 2;
    }
    gnuplot = plot::gnuplot::FindOnPath("gnuplot");
    if (gnuplot.empty()) {
        err << "gyrocal analyze: --plot " << plot::gnuplot::kGnuplotMissing << "\n";
        return 1;
    }
    return std::nullopt;
}

// What the options need before the analysis: valid analysis options, the --plot directory and
// gnuplot, and for --publish the store and the bus (opened now: a bad --lcm-url fails at once,
// not after minutes). Returns the exit code when the command must end now.
std::optional<int> PrepareAnalyze(const AnalyzeOptions& o, an::AnalysisOptions& ao,
                                  std::string& gnuplot, std::unique_ptr<bus::Bus>& bus,
                                  std::ostream& err) {
    ao = o.analysis;
    if (const std::string p = ao.Validate(); !p.empty()) {
        err << "gyrocal analyze: " << p << "\n";
        return 2;
    }
    if (!o.plot_dir.empty()) {
        if (const auto code = CheckPlotDir(o, gnuplot, err)) return code;
    }
    if (o.publish && !o.store) {
        err << "gyrocal analyze: --publish needs the result stored (drop --no-store): the "
               "published set's source names the stored analysis\n";
        return 2;
    }
    if (o.publish) {
        try {
            bus = std::make_unique<bus::Bus>(bus::BusOptions{o.lcm_url});
        } catch (const std::exception& e) {
            err << "gyrocal analyze: --lcm-url: " << e.what() << "\n";
            return 1;
        }
    }
    return std::nullopt;
}

// The sensors to analyse: --sensor's when it is in the run, else every sensor of the run.
// Returns the exit code when --sensor is not in the run.
std::optional<int> ChooseSensors(const AnalyzeOptions& o, const st::RunDetail& detail,
                                 std::vector<std::string>& sensors, std::ostream& err) {
    sensors = detail.run.sensor_ids;
    if (o.sensor_id.empty()) return std::nullopt;
    if (std::find(sensors.begin(), sensors.end(), o.sensor_id) == sensors.end()) {
        std::string known;
        for (const auto& s : sensors) known += (known.empty() ? "" : ", ") + s;
        err << "gyrocal analyze: --sensor '" << o.sensor_id << "' is not in run '" << o.run_id
            << "' (sensors: " << (known.empty() ? "none" : known) << ")\n";
        return 1;
    }
    sensors = {o.sensor_id};
    return std::nullopt;
}

// Each sensor's result, the utime of its run's last sample and, with --plot, its figures.
struct Analysed {
    std::vector<an::SensorResult> results;
    std::vector<int64_t> end_utimes;
    std::vector<plot::Figure> plots;
};

// Each unit's analysis on its own snapshot of the bins, two at a time (a day of one unit's
// analysis peaks at about 0.45 GB; the two cores of the development machine), in `sensors` order.
std::vector<an::SensorResult> AnalyseUnits(const an::AnalysisOptions& ao,
                                           const an::RunBinner& binned,
                                           const std::vector<std::string>& sensors) {
    std::vector<an::SensorResult> results(sensors.size());
    std::atomic<size_t> next{0};
    std::mutex mu;
    std::exception_ptr error;
    auto work = [&] {
        for (size_t i = next++; i < sensors.size(); i = next++) {
            try {
                results[i] = binned.Snapshot(sensors[i]).Analyze(ao);
            } catch (...) {
                std::lock_guard<std::mutex> lock(mu);
                if (!error) error = std::current_exception();
            }
        }
    };
    std::thread other(work);
    work();
    other.join();
    if (error) std::rethrow_exception(error);
    return results;
}

// --binned: every sensor binned in one pass over the run as it is read (LoadBinnedRun): memory per
// bin, not per sample, for runs too long to hold (a day of 16 units is ~9 GB of raw samples).
Analysed AnalyseBinned(const an::AnalysisOptions& ao, st::Db& db, const st::RunDetail& detail,
                       const std::vector<std::string>& sensors) {
    const an::RunBinner binned =
        LoadBinnedRun(db, detail, sensors, an::IncrementalOptions::For(ao));
    Analysed a;
    for (const std::string& id : sensors) {
        const an::UnitBinner* unit = binned.unit(id);
        if (!unit)
            throw std::runtime_error("run '" + detail.run.run_id + "': sensor " + id +
                                     " has no gyro samples");
        a.end_utimes.push_back(unit->newest_utime());
    }
    a.results = AnalyseUnits(ao, binned, sensors);
    return a;
}

Analysed AnalyseSensors(const AnalyzeOptions& o, const an::AnalysisOptions& ao, st::Db& db,
                        const st::RunDetail& detail, const std::vector<std::string>& sensors) {
    if (o.binned) return AnalyseBinned(ao, db, detail, sensors);
    const std::map<std::string, an::SensorRun> runs = LoadSensorRuns(db, detail, sensors);
    Analysed a;
    for (const std::string& id : sensors) {
        const an::SensorRun& run = runs.at(id);
        a.results.push_back(an::Analyze(run, ao));
        if (!o.plot_dir.empty())
            for (plot::Figure& f : an::MakePlots(run, a.results.back(), ao))
                a.plots.push_back(std::move(f));
        if (!o.plot_dir.empty()) AddAllanPlot(detail, id, a.plots);
        a.end_utimes.push_back(run.samples.empty() ? 0 : run.samples.back().utime);
    }
    return a;
}

st::AnalysisRow ToAnalysisRow(const AnalyzeOptions& o, const an::SensorResult& r) {
    st::AnalysisRow row;
    row.run_id = o.run_id;
    row.sensor_id = r.sensor_id;
    row.software_version = gyrocal::kSoftwareVersion;
    row.command_line = o.command_line;
    row.verdict = r.verdict;
    row.outcome = an::ToString(r.outcome);
    const nlohmann::json j = an::ToJson(r);
    row.candidates_json = j["candidates"].dump();
    row.added_json = j["added"].dump();
    an::CopyBeforeAfter(r, row);
    row.result_json = j.dump();
    return row;
}

// Publishes the stored extended model `set` on COEFFS_<id> under its stored source. Returns
// false when publishing failed (said on `err`).
bool PublishStored(bus::Bus& bus, const an::SensorResult& r,
                   const std::optional<model::CoeffSet>& set, const st::StoredAnalysis& stored,
                   std::ostream& err) {
    if (!set || !stored.coeff_row_id) {
        err << "gyrocal analyze: " << r.sensor_id
            << ": nothing published (no effect added: the declared model stands)\n";
        return true;
    }
    model::CoeffSet published = *set;
    published.source = stored.source;
    // ToMsg fills the length fields, so the message is whole or not sent at all.
    const gyrocal::coeff_set_t msg = model::ToMsg(published);
    if (!bus.Publish(channels::Coeffs(r.sensor_id), msg)) {
        err << "gyrocal analyze: " << r.sensor_id << ": publishing on "
            << channels::Coeffs(r.sensor_id) << " failed\n";
        return false;
    }
    err << "gyrocal analyze: " << r.sensor_id << ": published coefficient set " << msg.coeff_set_id
        << " (" << msg.source << ") on " << channels::Coeffs(r.sensor_id) << "\n";
    return true;
}

// Keeps each result (and its extended model) in the database and, with a bus, publishes the
// stored extended models. Returns the exit code: 0, or 1 when publishing failed.
int StoreResults(const AnalyzeOptions& o, const Analysed& a, bus::Bus* bus, std::ostream& err) {
    std::unique_ptr<st::Db> rw = st::OpenForUpdate(o.db);
    for (size_t i = 0; i < a.results.size(); ++i) {
        const an::SensorResult& r = a.results[i];
        // The extended model only when it differs from the declared one. Its id and time are the
        // run's last still sample (message time; the store sets the source).
        std::optional<model::CoeffSet> set;
        if (!r.added.empty()) set = an::ExtendedCoeffSet(r, o.run_id, "pending", a.end_utimes[i]);
        const st::StoredAnalysis stored =
            st::StoreAnalysis(*rw, ToAnalysisRow(o, r), set ? &*set : nullptr);
        err << "gyrocal analyze: " << r.sensor_id << ": stored as analysis " << stored.analysis_id
            << (stored.coeff_row_id ? ", extended model as coefficient set source " + stored.source
                                    : std::string())
            << "\n";
        if (bus && !PublishStored(*bus, r, set, stored, err)) return 1;
    }
    return 0;
}

// Draws the figures into --plot DIR (created now). Returns the exit code: 0, or 1 on failure.
int DrawPlots(const AnalyzeOptions& o, const std::string& gnuplot,
              const std::vector<plot::Figure>& plots, std::ostream& err) {
    std::error_code ec;
    fs::create_directory(o.plot_dir, ec);
    if (ec) {
        err << "gyrocal analyze: --plot " << o.plot_dir << ": " << ec.message() << "\n";
        return 1;
    }
    std::vector<std::string> images;
    try {
        images = plot::gnuplot::DrawInto(gnuplot, o.plot_dir, plots,
                                         {plot::Terminal::kPng, plot::Terminal::kSvg});
    } catch (const plot::gnuplot::GnuplotError& e) {
        err << "gyrocal analyze: --plot: " << e.what() << "\n";
        return 1;
    }
    err << "gyrocal analyze: wrote " << images.size() << " pictures to " << o.plot_dir << "\n";
    return 0;
}

// The whole command but the last-resort error line: options, analysis, store, pictures, report.
int AnalyzeRun(const AnalyzeOptions& o, std::ostream& out, std::ostream& err) {
    an::AnalysisOptions ao;
    std::string gnuplot;
    std::unique_ptr<bus::Bus> bus;
    if (const auto code = PrepareAnalyze(o, ao, gnuplot, bus, err)) return *code;
    std::unique_ptr<st::Db> db = st::OpenForQuery(o.db);
    const st::RunDetail detail = st::ShowRun(*db, o.run_id);
    std::vector<std::string> sensors;
    if (const auto code = ChooseSensors(o, detail, sensors, err)) return *code;
    const Analysed a = AnalyseSensors(o, ao, *db, detail, sensors);
    if (a.results.empty()) {
        err << "gyrocal analyze: run '" << o.run_id << "' has no sensors with samples\n";
        return 1;
    }
    if (o.store) {
        if (const int code = StoreResults(o, a, bus.get(), err); code != 0) return code;
    }
    if (!o.plot_dir.empty()) {
        if (const int code = DrawPlots(o, gnuplot, a.plots, err); code != 0) return code;
    }
    if (o.json) {
        out << an::ToJson(a.results).dump(2) << "\n";
    } else {
        out << "run " << o.run_id << " (" << db->path() << ")\n";
        for (const an::SensorResult& r : a.results) out << an::FormatReport(r);
    }
    return out ? 0 : 1;
}

}  // namespace

int RunAnalyze(const AnalyzeOptions& o, std::ostream& out, std::ostream& err) {
    return FailOnThrow(err, "gyrocal analyze: ", [&] { return AnalyzeRun(o, out, err); });
}

namespace {

// The verdict's thresholds as options (the surrogates aside), in the order --help lists them: each
// option's name, the field of the analysis options it sets, what it means and why its default
// (processors/analysis/README.md#thresholds-from-the-run-itself), and its valid values.
struct ThresholdOption {
    const char* name;
    double an::AnalysisOptions::*field;
    const char* help;
    CLI::Validator valid;
};

const std::vector<ThresholdOption>& ThresholdOptions() {
    using A = an::AnalysisOptions;
    static const std::vector<ThresholdOption> options = {
        {"--min-z2", &A::min_z2,
         "a candidate's coefficient^2 over its autocorrelation-robust variance must exceed this "
         "(25: 5 sigma, several candidates and searched shapes per step)",
         CLI::PositiveNumber},
        {"--min-cv-gain", &A::min_cv_gain,
         "relative drop of the blocked cross-validation error a candidate must give",
         CLI::Range(0.0, 0.99)},
        {"--max-collinearity", &A::max_collinearity,
         "above this |projected correlation| two candidates are ambiguous", CLI::Range(0.01, 0.99)},
        {"--min-pair-member-z2", &A::min_pair_member_z2,
         "each member of a collinear pair kept whole needs this z^2 with the other in",
         CLI::Range(0.0, 1e6)},
        {"--min-effect-floor-ratio", &A::min_effect_floor_ratio,
         "an added term's size over the 10 s-bin noise floor", CLI::Range(0.0, 100.0)},
        {"--min-feature-floor-ratio", &A::min_feature_floor_ratio,
         "an explaining feature's size over the floor (0.663: left out, it puts a model 1.2x "
         "above the floor on new data)",
         CLI::Range(0.0, 100.0)},
        {"--max-transfer-ratio", &A::max_transfer_ratio,
         "an explained model expected beyond this factor of the true model's error on another run "
         "(coefficients fitted on surrogates of the run's noise) is partly explained; 0: off",
         CLI::Range(0.0, 100.0)},
        {"--gate-min-z", &A::gate_min_z,
         "held-out improvement the chosen terms need, in its standard errors",
         CLI::Range(0.0, 100.0)},
        {"--max-untested-fraction", &A::max_untested_fraction,
         "'not testable' when more than this fraction of the candidates cannot be tested",
         CLI::Range(0.0, 1.0)},
        {"--slow-noise-floor-ratio", &A::slow_noise_floor_ratio,
         "k of the floor bound (slow noise over the floor); negative: measured from the run's "
         "Allan deviation",
         CLI::Range(-1.0, 10.0)},
        {"--feature-fpr", &A::feature_fpr,
         "family-wise false-positive rate of the generic features (null from surrogates of the "
         "run's noise)",
         CLI::Range(0.001, 0.49)},
        {"--window-fpr", &A::window_fpr,
         "family-wise false-positive rate of the time windows and temperature bands",
         CLI::Range(0.001, 0.49)},
        {"--warmup-fpr", &A::warmup_fpr, "false-positive rate of the warm-up's localized check",
         CLI::Range(0.001, 0.49)},
        {"--min-feature-drop", &A::min_feature_drop,
         "fraction of the held-out squared residual a feature must also remove (0: the calibrated "
         "null alone decides)",
         CLI::Range(0.0, 0.99)}};
    return options;
}

// The thresholds as options, for the stored command line.
std::string ThresholdArgs(const AnalyzeOptions& o) {
    std::string s;
    for (const ThresholdOption& t : ThresholdOptions())
        s += std::string(" ") + t.name + " " + text::Sig(o.analysis.*t.field, 6);
    return s + " --windows-statistic " + an::ToString(o.analysis.window_statistic) +
           " --surrogates " + std::to_string(o.analysis.surrogates) + " --surrogate-seed " +
           std::to_string(o.analysis.surrogate_seed) +
           (o.analysis.thermometer_lag_candidate ? " --thermometer-lag-candidate" : "");
}

// Every threshold of the verdict, and the surrogates its nulls are built from.
void AddThresholdOptions(CLI::App& sub, AnalyzeOptions& o) {
    for (const ThresholdOption& t : ThresholdOptions())
        sub.add_option(t.name, o.analysis.*t.field, t.help)->check(t.valid);
    sub.add_option_function<std::string>(
           "--windows-statistic",
           [&o](const std::string& name) {
               an::ParseWindowStatistic(name, &o.analysis.window_statistic);
           },
           "statistic of the windows test: plugin (each window's residual mean against "
           "surrogates of the run's fitted noise taken as exact: ~2x --window-fpr on clean runs) "
           "or studentised (the mean over the Allan deviation, at the window's length, of the "
           "noise refitted on the same vector, run and surrogates alike: near --window-fpr, but "
           "misses some effects the plug-in flags and costs 201 noise fits; "
           "processors/analysis/README.md)")
        ->check(CLI::IsMember({"plugin", "studentised"}))
        ->default_str(an::ToString(o.analysis.window_statistic));
    sub.add_flag("--thermometer-lag-candidate", o.analysis.thermometer_lag_candidate,
                 "also search thermometer_lag (dT*dTdt on the rate tracker: a thermometer lagging "
                 "the die); off by default: it adds wrong candidates on the verdict benchmark "
                 "(processors/analysis/README.md)");
    sub.add_option("--surrogates", o.analysis.surrogates,
                   "surrogates of the run's noise the nulls are built from")
        ->check(CLI::Range(20, 10000));
    sub.add_option("--surrogate-seed", o.analysis.surrogate_seed,
                   "seed of the surrogates (the same run and seed give the same verdict)");
}

}  // namespace

void AddAnalyzeCommand(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<AnalyzeOptions>();
    CLI::App* sub = app.add_subcommand(
        "analyze",
        "find what the declared model lacks in a recorded run: candidate effects tested out of "
        "sample, errors before/after on a held-out stretch, versus the noise floor");
    sub->option_defaults()->always_capture_default();  // --help shows every option's default
    sub->add_option("run", o->run_id, "run id (see `gyrocal runs`)")->required();
    sub->add_option("--sensor", o->sensor_id,
                    "analyse only this sensor (default: every sensor of the run)");
    sub->add_option("--db", o->db, "SQLite database the recorder wrote");
    sub->add_flag("--json", o->json, "print JSON (sensors[]) instead of the table");
    sub->add_option("--bin-s", o->analysis.bins.bin_s, "[s] bin length of the still data")
        ->check(CLI::Range(0.5, 600.0));
    sub->add_option("--holdout-fraction", o->analysis.holdout_fraction,
                    "fraction of the still data held out for the before/after figures and the "
                    "confirmation of added terms: one block of --holdout-block-s in round(1/F)")
        ->check(CLI::Range(0.05, 0.5));
    sub->add_option("--holdout-block-s", o->analysis.holdout_block_s,
                    "[s] length of the held-out blocks (interleaved with the training data)")
        ->check(CLI::Range(60.0, 86400.0));
    AddThresholdOptions(*sub, *o);
    CLI::Option* plot =
        sub->add_option("--plot", o->plot_dir,
                        "directory for pictures (gnuplot PNG + SVG, with their data and scripts); "
                        "created if its parent exists");
    sub->add_flag("--binned", o->binned,
                  "bin the run as it is read, every sensor in one pass (memory per 10 s bin, "
                  "not per sample: for day-long runs of many units); the same analysis, the "
                  "branch of untracked widths interpolated (processors/analysis/"
                  "bins_incremental.hpp); no --plot")
        ->excludes(plot);
    sub->add_flag("--publish", o->publish,
                  "publish each stored extended model on COEFFS_<id> for the live compensator");
    sub->add_option("--lcm-url", o->lcm_url,
                    "LCM URL for --publish (default: $GYROCAL_LCM_URL or the udpm default)");
    sub->add_flag("!--no-store", o->store,
                  "do not keep the result (and extended model) in the database");
    sub->footer(
        "Exit codes: 0 analysed (whatever the verdict), 1 failure (database missing or unreadable, "
        "run or sensor unknown, gnuplot missing or failing), 2 bad options (incl. a --plot DIR "
        "whose "
        "parent does not exist, --publish with --no-store).");
    sub->callback([o, &action] {
        // What was asked, as the options were understood (recorded with the stored analysis).
        o->command_line = "gyrocal analyze " + o->run_id + " --db " + o->db +
                          (o->sensor_id.empty() ? "" : " --sensor " + o->sensor_id) + " --bin-s " +
                          std::to_string(o->analysis.bins.bin_s) + " --holdout-fraction " +
                          std::to_string(o->analysis.holdout_fraction) + " --holdout-block-s " +
                          std::to_string(o->analysis.holdout_block_s) + ThresholdArgs(*o) +
                          (o->json ? " --json" : "") +
                          (o->plot_dir.empty() ? "" : " --plot " + o->plot_dir) +
                          (o->binned ? " --binned" : "") + (o->publish ? " --publish" : "");
        action = [o] { return RunAnalyze(*o, std::cout, std::cerr); };
    });
}

}  // namespace gyrocal::cli
