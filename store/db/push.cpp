#include "store/db/push.hpp"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "store/db/central_url.hpp"
#include "store/db/pg_connection.hpp"
#include "store/db/push_tables.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "store/db/utc_text.hpp"

namespace gyrocal::db {
namespace {

// A run refused on its own (the others go on).
class RunRefused : public StoreError {
public:
    using StoreError::StoreError;
};

std::string ThisHost() {
    char buf[256] = {};
    return gethostname(buf, sizeof buf - 1) == 0 ? std::string(buf) : std::string("unknown");
}

// What a run holds now, in one string: a run whose mark differs from its last push to a centre
// has something new to send (it ended, gained samples, sets, analyses, validations...).
std::string RunMark(Db& db, const std::string& run_id) {
    Stmt s(db,
           "SELECT r.outcome || '|' || coalesce(r.stopped_utime, '') || '|' || "
           "(SELECT coalesce(sum(n_samples), 0) FROM gyro_blocks WHERE run_id = ?1) || '|' || "
           "(SELECT count(*) FROM encoder_samples WHERE run_id = ?1) || '|' || "
           "(SELECT count(*) FROM plateaus WHERE run_id = ?1) || '|' || "
           "(SELECT count(*) FROM sensitivity_points WHERE run_id = ?1) || '|' || "
           "(SELECT coalesce(max(coeff_row_id), 0) FROM coeff_sets WHERE run_id = ?1) || '|' || "
           "(SELECT coalesce(max(analysis_id), 0) FROM analyses WHERE run_id = ?1) || '|' || "
           "(SELECT coalesce(max(validation_id), 0) FROM validations WHERE run_id = ?1) || '|' || "
           "(SELECT coalesce(max(noise_row_id), 0) FROM noise_estimates WHERE run_id = ?1) || '|' "
           "|| (SELECT coalesce(max(fit_report_row_id), 0) FROM fit_reports WHERE run_id = ?1) "
           "|| '|' || (SELECT count(*) FROM status WHERE run_id = ?1) "
           "FROM runs r WHERE r.run_id = ?1");
    s.Bind(1, run_id);
    return s.Step() ? s.Text(0) : std::string();
}

std::string Outcome(Db& db, const std::string& run_id) {
    Stmt s(db, "SELECT outcome FROM runs WHERE run_id = ?1");
    s.Bind(1, run_id);
    return s.Step() ? s.Text(0) : std::string();
}

// The run's identity as the centre compares it: start, first reception, host.
std::vector<std::string> Identity(Db& db, const std::string& run_id) {
    Stmt s(db,
           "SELECT coalesce(started_utime, ''), coalesce(first_recv_utime, ''), host FROM runs "
           "WHERE run_id = ?1");
    s.Bind(1, run_id);
    if (!s.Step()) return {};
    return {s.Text(0), s.Text(1), s.Text(2)};
}

// The run's key at the centre: its run_origins row, made now on its first push. Throws RunRefused
// when the centre has another run of that id.
int64_t RunKey(pqxx::work& tx, Db& station, const std::string& run_id, const PushOptions& o,
               const std::string& host) {
    const pqxx::result origin = tx.exec_params(
        "SELECT run_key, station_host, station_db FROM run_origins WHERE run_id = $1", run_id);
    const pqxx::result central = tx.exec_params(
        "SELECT coalesce(started_utime::text, ''), coalesce(first_recv_utime::text, ''), host "
        "FROM runs WHERE run_id = $1",
        run_id);
    const std::vector<std::string> mine = Identity(station, run_id);
    if (!central.empty()) {
        const std::vector<std::string> theirs = {central[0][0].c_str(), central[0][1].c_str(),
                                                 central[0][2].c_str()};
        const std::string from = origin.empty() ? std::string("no recorded station")
                                                : "station " + std::string(origin[0][1].c_str()) +
                                                      ":" + origin[0][2].c_str();
        if (origin.empty() || theirs != mine) {
            throw RunRefused("run '" + run_id + "' is at the centre already as another run (" +
                             from + ", started_utime " + theirs[0] + ", host '" + theirs[2] +
                             "'): not pushed; run ids must be unique across stations");
        }
    }
    if (!origin.empty()) return origin[0][0].as<int64_t>();
    const pqxx::result k = tx.exec_params(
        "INSERT INTO run_origins(run_id, station_host, station_db, station_software_version, "
        "station_schema_version, first_pushed_wall_utime) VALUES ($1, $2, $3, $4, $5, $6) "
        "RETURNING run_key",
        run_id, host, std::filesystem::absolute(o.station_db).lexically_normal().string(),
        o.software_version, kSchemaVersion, WallUtimeNow());
    return k[0][0].as<int64_t>();
}

// Refuses a centre that cannot take this station's rows, before anything is written.
void CheckCentral(CentralConnection& c) {
    int version = 0;
    try {
        pqxx::work tx(c.conn());
        version = CentralSchemaVersion(tx);
        tx.commit();
    } catch (const std::exception& e) {
        c.Fail(e, "reading its schema version");
    }
    const std::string where = "central database '" + c.name() + "'";
    if (version < 0)
        throw CentralError(where +
                               " is not a gyrocal database (it holds other tables and no "
                               "gyrocal_meta): nothing written",
                           "", false);
    if (version == 0)
        throw CentralError(where +
                               " has no gyrocal schema: create it first with gyrocal central "
                               "init --db URL (as the database's owner); nothing written",
                           "", false);
    if (version < kSchemaVersion)
        throw CentralError(where + " has schema version " + std::to_string(version) +
                               ", older than this station's (" + std::to_string(kSchemaVersion) +
                               "): nothing written; migrate the centre first with gyrocal "
                               "central init --db URL (as its owner)",
                           "", false);
}

void RecordPush(const PushOptions& o, const std::string& central, const std::string& run_id,
                const std::string& outcome, const std::string& mark, const RunPush& r) {
    Db rw(o.station_db, Db::Mode::kReadWrite);
    ConfigureConnection(rw);
    Stmt(rw,
         "INSERT INTO pushes(run_id, central, pushed_wall_utime, run_outcome, run_mark, "
         "rows_added, rows_updated) VALUES (?,?,?,?,?,?,?)")
        .BindAll(run_id, central, WallUtimeNow(), outcome, mark, r.rows_added, r.rows_updated)
        .Run();
}

// One run, in one central transaction, from one station snapshot.
RunPush PushOne(Db& station, const std::vector<push::Table>& tables, CentralConnection& c,
                const std::string& run_id, const PushOptions& o, const std::string& host) {
    RunPush r;
    r.run_id = run_id;
    const auto t0 = std::chrono::steady_clock::now();
    station.Exec("BEGIN");  // a read snapshot: the recorder may go on writing meanwhile
    std::string outcome, mark;
    try {
        outcome = Outcome(station, run_id);
        mark = RunMark(station, run_id);
        pqxx::work tx(c.conn());
        // One push of a run at a time (two shells, or the recorder's push and a manual one).
        tx.exec_params("SELECT pg_advisory_xact_lock(hashtext($1))", "gyrocal push " + run_id);
        push::RunCopy copy{station, tx, run_id, RunKey(tx, station, run_id, o, host), 0, 0, 0, {}};
        push::LoadWatermarks(tables, copy);
        for (const push::Table& t : tables) push::CopyTable(t, copy);
        tx.commit();
        r.rows_added = copy.rows_added;
        r.rows_updated = copy.rows_updated;
        r.samples_added = copy.samples_added;
        r.ok = true;
    } catch (const RunRefused& e) {
        r.error = e.what();
    } catch (const CentralError&) {
        station.Exec("COMMIT");
        throw;
    } catch (const StoreError&) {
        station.Exec("COMMIT");
        throw;
    } catch (const std::exception& e) {
        station.Exec("COMMIT");
        c.Fail(e, "pushing run '" + run_id + "'");
    }
    station.Exec("COMMIT");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.ok) RecordPush(o, c.name(), run_id, outcome, mark, r);
    return r;
}

// The runs named, checked before anything is sent.
void CheckNamedRuns(Db& station, const PushOptions& o) {
    for (const std::string& id : o.run_ids) {
        if (id.empty()) throw NotFound("'' is the no-run bucket, not a run: it is not pushed");
        RequireRun(station, id);
        if (!o.include_open && Outcome(station, id) == "running") {
            throw StoreError("run '" + id +
                             "' is still open (running): push it when it has "
                             "ended, or now up to what is recorded with --include-open");
        }
    }
}

}  // namespace

bool WaitUntilEnded(const std::string& station_db, const std::string& run_id, double timeout_s) {
    const auto give_up =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
        {
            auto db = OpenForQuery(station_db);
            const std::string outcome = Outcome(*db, run_id);
            if (!outcome.empty() && outcome != "running") return true;
        }
        if (std::chrono::steady_clock::now() >= give_up) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
}

std::vector<std::string> RunsToPush(const std::string& station_db, const std::string& central_url,
                                    bool include_open) {
    auto db = OpenForQuery(station_db);
    const std::string central = WithoutCredentials(central_url);
    std::vector<std::string> out;
    Stmt s(*db,
           "SELECT run_id FROM runs WHERE run_id != '' AND (outcome != 'running' OR ?1) "
           "ORDER BY first_recv_utime, rowid");
    s.Bind(1, int64_t{include_open ? 1 : 0});
    Stmt last(*db,
              "SELECT run_mark FROM pushes WHERE central = ?1 AND run_id = ?2 "
              "ORDER BY push_id DESC LIMIT 1");
    while (s.Step()) {
        const std::string id = s.Text(0);
        last.Bind(1, central).Bind(2, id);
        const bool pushed = last.Step();
        const std::string mark = pushed ? last.Text(0) : std::string();
        last.Reset();
        if (!pushed || mark != RunMark(*db, id)) out.push_back(id);
    }
    return out;
}

PushReport Push(const PushOptions& o) {
    if (IsCentralUrl(o.station_db))
        throw StoreError("--db must be the station's SQLite file, not a central database");
    if (!IsCentralUrl(o.central_url))
        throw StoreError("'" + WithoutCredentials(o.central_url) +
                         "' is not a central database URL (postgresql://[user@]host[:port]/db)");
    auto station = OpenForQuery(o.station_db);
    CheckNamedRuns(*station, o);
    const std::vector<push::Table> tables = push::StationTables(*station);
    const std::vector<std::string> runs =
        o.run_ids.empty() ? RunsToPush(o.station_db, o.central_url, o.include_open) : o.run_ids;
    CentralConnection c(o.central_url);
    CheckCentral(c);
    PushReport report;
    report.central = c.name();
    const std::string host = o.host.empty() ? ThisHost() : o.host;
    for (const std::string& id : runs) {
        report.runs.push_back(PushOne(*station, tables, c, id, o, host));
        const RunPush& r = report.runs.back();
        if (o.log) {
            o.log(r.ok ? "run " + id + ": " + std::to_string(r.rows_added) + " rows added (" +
                             std::to_string(r.samples_added) + " gyro samples), " +
                             std::to_string(r.rows_updated) + " updated"
                       : "run " + id + ": " + r.error);
        }
    }
    return report;
}

}  // namespace gyrocal::db
