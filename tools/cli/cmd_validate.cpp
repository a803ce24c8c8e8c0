#include "tools/cli/cmd_validate.hpp"

#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "gyrocal/version.hpp"
#include "processors/analysis/validate.hpp"
#include "store/db/analyses.hpp"
#include "store/db/query.hpp"
#include "store/db/validations.hpp"
#include "tools/cli/cmd_compensate.hpp"
#include "tools/cli/command.hpp"
#include "tools/cli/run_loader.hpp"

namespace gyrocal::cli {

namespace an = gyrocal::analysis;
namespace st = gyrocal::db;

namespace {

// "" when exactly one model source is given, else what is wrong.
std::string SourceProblem(const ValidateOptions& o) {
    const int n = !o.model_run_id.empty() + o.coeff_set_row.has_value() + !o.coeffs_path.empty();
    if (n != 1)
        return "give exactly one model: --model-run RUN, --coeff-set-row N or --coeffs FILE";
    if (o.model_run_id == o.run_id)
        return "--model-run is the run being validated: validate a model on a run it was not "
               "fitted on";
    return "";
}

st::ValidationRow Row(const ValidateOptions& o, const an::ValidationResult& r) {
    st::ValidationRow row;
    row.run_id = o.run_id;
    row.sensor_id = r.sensor_id;
    row.software_version = kSoftwareVersion;
    row.command_line = o.command_line;
    row.model_origin = r.model_origin;
    row.coeff_row_id = o.coeff_set_row;
    row.model_run_id = o.model_run_id;
    row.n_bins = r.n_bins;
    row.offset_rms_v = r.offset_rms_v;
    row.rate_rms_dps = r.rate_rms_dps;
    row.drift_dph = r.drift_dph;
    row.floor_rate_rms_dps = r.floor_rate_rms_dps;
    row.power_on = r.power_on;
    row.result_json = an::ToJson(r).dump();
    return row;
}

}  // namespace

int RunValidate(const ValidateOptions& o, std::ostream& out, std::ostream& err) {
    const char* me = "gyrocal validate: ";
    if (const std::string p = SourceProblem(o); !p.empty()) {
        err << me << p << "\n";
        return 2;
    }
    return FailOnThrow(err, me, [&] {
        std::string origin;
        const std::map<std::string, model::CoeffSet> sets =
            LoadCoeffSets({o.coeffs_path, o.coeffs_path.empty() ? o.db : "", o.model_run_id,
                           o.sensor_id, o.coeff_set_row},
                          &origin);
        std::unique_ptr<st::Db> db = st::OpenForQuery(o.db);
        const st::RunDetail detail = st::ShowRun(*db, o.run_id);
        std::vector<std::string> sensors;
        for (const std::string& id : detail.run.sensor_ids)
            if (sets.count(id) && (o.sensor_id.empty() || o.sensor_id == id)) sensors.push_back(id);
        if (sensors.empty())
            throw st::NotFound("no sensor of run '" + o.run_id + "' has a model in " + origin);
        const auto runs = LoadSensorRuns(*db, detail, sensors);
        an::BinOptions bins;
        bins.bin_s = o.bin_s;
        nlohmann::json all = nlohmann::json::array();
        std::unique_ptr<st::Db> rw = o.store ? st::OpenForUpdate(o.db) : nullptr;
        int failed = 0;
        for (const std::string& id : sensors) {
            const an::ValidationResult r = an::Validate(runs.at(id), sets.at(id), origin, bins);
            if (!std::isfinite(r.rate_rms_dps)) {
                // No figures (no still data, or an input the run lacks): a failure, not a result;
                // nothing is stored for it, the other sensors still are.
                std::string why;
                for (const std::string& n : r.notes) why += (why.empty() ? "" : "; ") + n;
                err << me << "run '" << o.run_id << "' sensor " << id
                    << ": nothing to validate on (" << (why.empty() ? "no figures" : why)
                    << "); a run needs still data the model's inputs cover\n";
                ++failed;
                continue;
            }
            if (rw) {
                const int64_t vid = st::InsertValidation(*rw, Row(o, r));
                err << me << id << ": stored as validation " << vid << "\n";
            }
            if (o.json)
                all.push_back(an::ToJson(r));
            else
                out << an::FormatValidation(r);
        }
        if (o.json && !all.empty())
            out << nlohmann::json{{"run_id", o.run_id}, {"sensors", all}}.dump(2) << "\n";
        return out && failed == 0 ? 0 : 1;
    });
}

void AddValidateCommand(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<ValidateOptions>();
    auto row = std::make_shared<int64_t>(0);
    CLI::App* sub = app.add_subcommand(
        "validate",
        "apply a stored model to another run of the same units (a second chamber run, a ramp run) "
        "and report its error on that run's still data against the run's floor");
    sub->add_option("run", o->run_id, "the run to validate on (see `gyrocal runs`)")->required();
    sub->add_option("--db", o->db, "SQLite database the recorder wrote")->capture_default_str();
    sub->add_option("--model-run", o->model_run_id, "the newest set of each sensor of this run");
    auto* r = sub->add_option("--coeff-set-row", *row, "this stored coefficient set (row id)");
    sub->add_option("--coeffs", o->coeffs_path,
                    "the sets of a JSON export (`gyrocal export --format json`)");
    sub->add_option("--sensor", o->sensor_id, "only this sensor");
    sub->add_option("--bin-s", o->bin_s, "[s] bin length of the still data")
        ->check(CLI::Range(0.5, 600.0))
        ->capture_default_str();
    sub->add_flag("--json", o->json, "print JSON instead of the table");
    sub->add_flag("!--no-store", o->store, "do not keep the result in the database");
    sub->footer(
        "Exit codes: 0 validated (whatever the figures), 1 failure (database, run, sensor or "
        "model missing or unusable, or a sensor without still data to validate on), 2 bad "
        "options.");
    sub->callback([o, row, r, &action] {
        if (r->count()) o->coeff_set_row = *row;
        o->command_line = "gyrocal validate " + o->run_id + " --db " + o->db +
                          (o->model_run_id.empty() ? "" : " --model-run " + o->model_run_id) +
                          (r->count() ? " --coeff-set-row " + std::to_string(*row) : "") +
                          (o->coeffs_path.empty() ? "" : " --coeffs " + o->coeffs_path) +
                          (o->sensor_id.empty() ? "" : " --sensor " + o->sensor_id);
        action = [o] { return RunValidate(*o, std::cout, std::cerr); };
    });
}

}  // namespace gyrocal::cli
