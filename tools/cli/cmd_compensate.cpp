#include "tools/cli/cmd_compensate.hpp"

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "lcmtypes/process/renamed_option.hpp"
#include "processors/compensator/offline.hpp"
#include "producers/csv/conversion_options.hpp"
#include "producers/csv/csv_file.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/query.hpp"
#include "store/db/sqlite_db.hpp"
#include "tools/cli/command.hpp"

namespace gyrocal::cli {

namespace cp = gyrocal::compensator;
namespace st = gyrocal::db;

std::map<std::string, model::CoeffSet> LoadCoeffSets(const CoeffSource& o, std::string* origin) {
    std::map<std::string, model::CoeffSet> sets;
    if (!o.coeffs_path.empty()) {
        std::ifstream f(o.coeffs_path, std::ios::binary);
        if (!f) throw cp::OfflineError("--coeffs: cannot read '" + o.coeffs_path + "'");
        std::ostringstream text;
        text << f.rdbuf();
        *origin = o.coeffs_path;
        sets = cp::CoeffSetsFromJson(text.str(), o.coeffs_path);
        if (!o.sensor_id.empty()) {
            const auto it = sets.find(o.sensor_id);
            if (it == sets.end())
                throw cp::OfflineError(o.coeffs_path + ": no coefficient set for --sensor '" +
                                       o.sensor_id + "'");
            sets = {{it->first, it->second}};
        }
        return sets;
    }
    std::unique_ptr<st::Db> db = st::OpenForQuery(o.db);
    const std::string name = db->path();  // a central URL without its credentials
    std::vector<st::CoeffSetInfo> infos;
    if (o.coeff_set_row) {
        st::Stmt q(*db, "SELECT sensor_id FROM coeff_sets WHERE coeff_row_id = ?");
        q.Bind(1, *o.coeff_set_row);
        if (!q.Step())
            throw st::NotFound("--coeff-set-row " + std::to_string(*o.coeff_set_row) +
                               ": no such coefficient set in '" + name +
                               "' (see gyrocal history SENSOR)");
        const std::string sensor = q.Text(0);
        for (const st::CoeffSetInfo& c : st::SensorHistory(*db, sensor, false))
            if (c.coeff_row_id == *o.coeff_set_row) infos.push_back(c);
        *origin = name + " coefficient set row " + std::to_string(*o.coeff_set_row);
    } else if (!o.run_id.empty()) {
        for (const st::CoeffSetInfo& c : st::RunNewestCoeffs(*db, o.run_id))
            if (o.sensor_id.empty() || c.set.sensor_id == o.sensor_id) infos.push_back(c);
        *origin = name + " run '" + o.run_id + "' (newest sets)";
        if (infos.empty())
            throw st::NotFound("run '" + o.run_id + "' of '" + name + "' has no coefficient set" +
                               (o.sensor_id.empty() ? "" : " for sensor '" + o.sensor_id + "'"));
    } else {
        const auto all = st::SensorHistory(*db, o.sensor_id, false);
        if (all.empty())
            throw st::NotFound("sensor '" + o.sensor_id + "' has no coefficient set in '" + name +
                               "'");
        infos.push_back(all.back());
        *origin = name + " sensor '" + o.sensor_id + "' (newest set)";
    }
    for (const st::CoeffSetInfo& c : infos) {
        model::CoeffSet set = st::ToCoeffSet(c.set);
        sets[set.sensor_id] = set;
    }
    return sets;
}

int RunCompensate(const CompensateOptions& o, std::ostream& out, std::ostream& err) {
    const char* me = "gyrocal compensate: ";
    // Options first (exit 2): exactly one coefficient source, valid conversion options.
    const bool from_db = !o.db.empty();
    if (from_db == !o.coeffs_path.empty()) {
        err << me << "give exactly one coefficient source: --coeffs FILE or --db FILE\n";
        return 2;
    }
    if (from_db && (!o.run_id.empty()) + o.coeff_set_row.has_value() +
                           (o.run_id.empty() && !o.coeff_set_row && !o.sensor_id.empty()) !=
                       1) {
        err << me
            << "with --db give one of: --run RUN [--sensor ID], --sensor ID, --coeff-set-row N\n";
        return 2;
    }
    if (!from_db && (!o.run_id.empty() || o.coeff_set_row)) {
        err << me << "--run and --coeff-set-row need --db\n";
        return 2;
    }
    const auto policy = model::ParseRangePolicy(o.range_policy);
    if (!policy) {
        err << me << "--out-of-range '" << o.range_policy
            << "' is not valid: use clip or extrapolate\n";
        return 2;
    }
    csv::ConversionOptions conv;
    conv.preset = o.preset;
    conv.temp_v_at_25c = o.temp_v_at_25c;
    conv.temp_v_per_c = o.temp_v_per_c;
    std::string terr;
    const auto transfer = conv.Transfer(&terr);
    if (!transfer) {
        err << me << terr << "\n";
        return 2;
    }
    return FailOnThrow(err, me, [&] {
        std::string origin;
        const std::map<std::string, model::CoeffSet> sets =
            LoadCoeffSets({o.coeffs_path, o.db, o.run_id, o.sensor_id, o.coeff_set_row}, &origin);
        std::ifstream in(o.csv_path, std::ios::binary);
        if (!in) {
            err << me << "cannot read CSV '" << o.csv_path << "'\n";
            return 1;
        }
        const csv::CsvFile file = csv::ReadCsv(in, o.csv_path, *transfer, csv::OnError::kStop);
        if (file.rows.empty()) {
            err << me << o.csv_path << ": no data rows\n";
            return 1;
        }
        cp::OfflineOptions oo;
        oo.core.range_policy = *policy;
        const cp::OfflineResult r = cp::CompensateRows(file.rows, sets, o.csv_path, origin, oo);
        const std::string text = cp::FormatRatesCsv(r.rates);
        if (o.out_path.empty()) {
            out << text;
            if (!out.flush()) return 1;
        } else {
            std::ofstream f(o.out_path, std::ios::binary | std::ios::trunc);
            if (f) f << text;
            if (f) f.close();
            if (!f) {
                err << me << "--out: cannot write '" << o.out_path << "'\n";
                return 1;
            }
        }
        err << me << r.rates.size() << " samples compensated with " << origin;
        if (r.skipped > 0)
            err << "; " << r.skipped
                << " not computable (the live compensator would not publish them either; first "
                << r.first_skip << ")";
        err << "\n";
        return 0;
    });
}

void AddCompensateCommand(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<CompensateOptions>();
    auto row = std::make_shared<int64_t>(0);
    auto v25 = std::make_shared<double>(0.0);
    auto vpc = std::make_shared<double>(0.0);
    CLI::App* sub = app.add_subcommand(
        "compensate",
        "apply a stored coefficient set (or its JSON export) to measured data in a CSV and write "
        "the compensated rate per sample, as the live compensator would");
    sub->add_option("csv", o->csv_path,
                    "measured data (time_s, sensor_id, gyro_v, temp_v[, temp_c, supply_v, ...])")
        ->required();
    sub->add_option("--coeffs", o->coeffs_path,
                    "JSON coefficient sets as `gyrocal export --format json` writes");
    sub->add_option("--db", o->db, "SQLite database the recorder wrote (instead of --coeffs)");
    sub->add_option("--run", o->run_id, "with --db: the newest set of each sensor of this run");
    sub->add_option("--sensor", o->sensor_id,
                    "only this sensor (with --run or --coeffs); alone with --db: its newest set");
    auto* r = sub->add_option("--coeff-set-row", *row, "with --db: this stored set (row id)");
    sub->add_option("--out", o->out_path, "write the CSV here instead of stdout");
    sub->add_option("--out-of-range", o->range_policy,
                    "outside a model's valid temperature range: clip or extrapolate")
        ->capture_default_str();
    sub->add_option("--preset", o->preset,
                    "module preset for temp_v -> temp_c when the CSV has no temp_c: 610 or 613")
        ->capture_default_str();
    auto* a = sub->add_option("--temp-v-at-25c", *v25, "[V] temperature output at 25 degC");
    auto* k = sub->add_option("--temp-v-per-c", *vpc, "[V/degC] temperature output slope");
    auto* old_k = process::AddOldOptionName<double>(*sub, k, "--temp-v-per-k", *vpc);
    sub->footer(
        "Exit codes: 0 written, 1 failure (bad CSV, bad or missing coefficients, a sensor without "
        "a set, database unreadable, output not writable), 2 bad options.");
    sub->callback([o, row, v25, vpc, r, a, k, old_k, &action] {
        if (r->count()) o->coeff_set_row = *row;
        if (a->count()) o->temp_v_at_25c = *v25;
        if (k->count() || old_k->count()) o->temp_v_per_c = *vpc;
        action = [o] { return RunCompensate(*o, std::cout, std::cerr); };
    });
}

}  // namespace gyrocal::cli
