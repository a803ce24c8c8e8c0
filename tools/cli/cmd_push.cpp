// `gyrocal push` and `gyrocal central`: thin CLI over the push library and the central schema
// (store/db/push.hpp, central_db.hpp). Every message names the central database without its
// credentials.
#include "tools/cli/cmd_push.hpp"

#include <cstdlib>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gyrocal/version.hpp"
#include "store/db/central_db.hpp"
#include "store/db/central_url.hpp"
#include "store/db/push.hpp"
#include "tools/cli/command.hpp"

namespace gyrocal::cli {
namespace {

namespace st = gyrocal::db;

// --to, or $GYROCAL_CENTRAL_URL.
std::string CentralUrl(const std::string& given) {
    if (!given.empty()) return given;
    const char* env = std::getenv("GYROCAL_CENTRAL_URL");
    if (env && *env) return env;
    throw std::runtime_error(
        "no central database: give --to postgresql://[user@]host[:port]/db or set "
        "GYROCAL_CENTRAL_URL");
}

struct PushCli {
    std::string to, db = "gyrocal.db";
    std::vector<std::string> runs;
    bool include_open = false, dry_run = false, json = false;
    std::string wait_ended;  // push once this run has ended in the station file
    double wait_s = 60;
};

nlohmann::json ReportJson(const st::PushReport& r) {
    nlohmann::json runs = nlohmann::json::array();
    for (const st::RunPush& p : r.runs) {
        runs.push_back({{"run_id", p.run_id},
                        {"ok", p.ok},
                        {"rows_added", p.rows_added},
                        {"rows_updated", p.rows_updated},
                        {"gyro_samples_added", p.samples_added},
                        {"seconds", p.seconds},
                        {"error", p.error}});
    }
    return {{"central", r.central}, {"runs", runs}, {"failed", r.failed()}};
}

int RunPush(const PushCli& o, std::ostream& out, std::ostream& err) {
    st::PushOptions po;
    po.station_db = o.db;
    po.central_url = CentralUrl(o.to);
    po.run_ids = o.runs;
    po.include_open = o.include_open;
    po.software_version = kSoftwareVersion;
    if (!o.wait_ended.empty() && !st::WaitUntilEnded(o.db, o.wait_ended, o.wait_s)) {
        throw std::runtime_error("run '" + o.wait_ended + "' has not ended in '" + o.db +
                                 "' after " + std::to_string(static_cast<int>(o.wait_s)) +
                                 " s: nothing pushed");
    }
    if (o.dry_run) {
        for (const std::string& id : st::RunsToPush(o.db, po.central_url, o.include_open))
            out << id << "\n";
        return 0;
    }
    if (!o.json) po.log = [&out](const std::string& line) { out << line << "\n" << std::flush; };
    const st::PushReport r = st::Push(po);
    for (const st::RunPush& p : r.runs)
        if (!p.ok) err << "gyrocal push: run " << p.run_id << ": " << p.error << "\n";
    if (o.json) {
        out << ReportJson(r).dump(2) << "\n";
    } else if (r.runs.empty()) {
        out << "nothing new to push to " << r.central << "\n";
    } else {
        out << r.runs.size() - static_cast<size_t>(r.failed()) << " of " << r.runs.size()
            << " runs pushed to " << r.central << "\n";
    }
    return r.failed() == 0 ? 0 : 1;
}

void AddPush(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<PushCli>();
    CLI::App* sub = app.add_subcommand(
        "push",
        "send this station's runs to the lab's central PostgreSQL database (store and forward:\n"
        "each run whole in one transaction, exactly once; what was pushed is recorded here)");
    sub->add_option("runs", o->runs,
                    "run ids (default: every finished run with something new for that centre)");
    sub->add_option("--to", o->to,
                    "central database: postgresql://[user@]host[:port]/db[?sslmode=...] "
                    "(default $GYROCAL_CENTRAL_URL; password from ~/.pgpass, PGPASSFILE or "
                    "PGPASSWORD rather than the URL)");
    sub->add_option("--db", o->db, "this station's SQLite database")->capture_default_str();
    sub->add_flag("--include-open", o->include_open,
                  "also runs still being recorded, up to what is committed (a later push sends "
                  "the rest; needs UPDATE on runs and losses at the centre)");
    sub->add_flag("--dry-run", o->dry_run, "list the runs that would be pushed, send nothing");
    sub->add_option("--wait-ended", o->wait_ended,
                    "first wait until this run has ended in the station file (its stop "
                    "committed), then push what is new (how gyrocal-recorder --push-to calls it)");
    sub->add_option("--wait-s", o->wait_s, "[s] how long --wait-ended waits")
        ->check(CLI::Range(0.0, 86400.0))
        ->capture_default_str();
    sub->add_flag("--json", o->json, "print the result as JSON");
    sub->footer(
        "Exit codes: 0 every run pushed (or nothing new), 1 a failure (station file, centre "
        "unreachable or refusing, a run not pushed), 2 bad options.");
    sub->callback([o, &action] {
        action = [o] {
            return FailOnThrow(std::cerr, "gyrocal push: error: ", [&] {
                return RunPush(*o, std::cout, std::cerr);
            });
        };
    });
}

void AddCentral(CLI::App& app, std::function<int()>& action) {
    CLI::App* sub = app.add_subcommand(
        "central", "the lab's central database: create or migrate its schema, grant, status");
    sub->require_subcommand(1);
    sub->footer("Exit codes: 0 success, 1 failure, 2 bad options.");

    auto url = std::make_shared<std::string>();
    auto push_roles = std::make_shared<std::vector<std::string>>();
    auto read_roles = std::make_shared<std::vector<std::string>>();
    auto updates = std::make_shared<bool>(false);
    CLI::App* init = sub->add_subcommand(
        "init",
        "create the gyrocal schema in an empty database, or migrate an older one "
        "(as the database's owner), and grant roles");
    init->add_option("--db", *url, "central database postgresql://...")->required();
    init->add_option("--grant-push", *push_roles,
                     "role(s) that push: INSERT and SELECT on gyrocal's tables");
    init->add_option("--grant-read", *read_roles, "role(s) that only read: SELECT");
    init->add_flag("--allow-open-runs", *updates,
                   "also grant the push roles UPDATE on runs and losses (push --include-open)");
    init->callback([&action, url, push_roles, read_roles, updates] {
        action = [=] {
            return FailOnThrow(std::cerr, "gyrocal central init: error: ", [&] {
                const int found = st::InitCentral(*url);
                for (const auto& r : *push_roles) st::GrantCentral(*url, r, false, *updates);
                for (const auto& r : *read_roles) st::GrantCentral(*url, r, true, false);
                std::cout << st::WithoutCredentials(*url) << ": schema version "
                          << (found == 0 ? "0 (new)" : std::to_string(found)) << " -> "
                          << st::ReadCentralStatus(*url).schema_version << "\n";
                return 0;
            });
        };
    });

    auto status_url = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* status = sub->add_subcommand("status", "schema version, runs, stations, TLS");
    status->add_option("--db", *status_url, "central database postgresql://...")->required();
    status->add_flag("--json", *json, "JSON instead of text");
    status->callback([&action, status_url, json] {
        action = [=] {
            return FailOnThrow(std::cerr, "gyrocal central status: error: ", [&] {
                const st::CentralStatus s = st::ReadCentralStatus(*status_url);
                nlohmann::json j = {{"central", s.name},
                                    {"schema_version", s.schema_version},
                                    {"server_version", s.server_version},
                                    {"runs", s.runs},
                                    {"stations", s.stations},
                                    {"tls", s.ssl}};
                if (*json) {
                    std::cout << j.dump(2) << "\n";
                } else {
                    std::cout << s.name << ": PostgreSQL " << s.server_version
                              << ", gyrocal schema version " << s.schema_version << ", " << s.runs
                              << " runs from " << s.stations << " stations, connection "
                              << (s.ssl ? "encrypted (TLS)" : "not encrypted") << "\n";
                }
                return 0;
            });
        };
    });
}

}  // namespace

void AddPushCommands(CLI::App& app, std::function<int()>& action) {
    AddPush(app, action);
    AddCentral(app, action);
}

}  // namespace gyrocal::cli
