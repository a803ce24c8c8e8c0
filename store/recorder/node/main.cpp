// gyrocal-recorder: every message on the bus into SQLite. The node, its threads and how it stops
// are in recorder_node.hpp; this file parses the options and opens the database.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <string>

#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "store/recorder/node/recorder_node.hpp"

int main(int argc, char** argv) {
    using gyrocal::recorder::node::kRecorderProcess;
    auto o = gyrocal::recorder::node::RecorderOptions::Defaults();
    CLI::App app{
        "gyrocal-recorder: records every LCM message into an SQLite database (WAL, batched).\n"
        "Known types go to their tables, unknown ones to raw_events; runs follow RUN_EVENT.\n"
        "A SIGKILL loses at most the last --batch-ms of data (plus one commit).\n"
        "Database on a full disk, read-only or locked: STATUS state db_blocked:<fault> and a log\n"
        "line; received rows wait in memory (up to --queue-rows) and are written when it can\n"
        "again; rows beyond the bound are counted in losses.queue_drops by run and channel.\n"
        "Exit codes: 0 normal stop (SIGINT/SIGTERM), 1 runtime failure (database write, LCM),\n"
        "2 bad options (including a --db that cannot be opened or is not a gyrocal database).",
        kRecorderProcess};
    app.add_option("--db", o.db_path, "SQLite database file (created when missing)");
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default $GYROCAL_LCM_URL or udpm default)");
    app.add_option("--channels", o.channels, "LCM channel regex to record")
        ->check(CLI::Validator(
            [](std::string& text) {
                return gyrocal::recorder::node::ValidateLcmChannelRegex(text);
            },
            "REGEX"))
        ->capture_default_str();
    app.add_flag("--no-rates", o.no_rates, "do not store RATE_* (compensated rate) messages");
    app.add_option("--push-to", o.push_to,
                   "central database postgresql://...: when a run ends, push it there in the "
                   "background (gyrocal push; recording never waits on it; password from "
                   "PGPASSFILE rather than the URL)");
    app.add_option(
           "--queue-rows", o.queue_rows,
           "rows held in memory (queued, or waiting for a blocked database) before dropping")
        ->check(CLI::Range(size_t{1000}, size_t{100000000}))
        ->capture_default_str();
    app.add_option("--batch-rows", o.batch_rows, "commit every N rows")
        ->check(CLI::Range(size_t{1}, size_t{1000000}))
        ->capture_default_str();
    app.add_option("--batch-ms", o.batch_ms, "commit at least every N ms (crash loss bound)")
        ->check(CLI::Range(1, 60000))
        ->capture_default_str();
    // The options check themselves (CLI::Range, the channel regex); --db is checked by opening it.
    if (auto exit_code = gyrocal::process::ParseCommandLine(app, argc, argv, kRecorderProcess))
        return *exit_code;

    std::unique_ptr<gyrocal::db::StoreWriter> writer;
    try {
        writer = gyrocal::recorder::node::OpenRecorderDatabase(o.db_path);
    } catch (const std::exception& e) {
        gyrocal::process::PrintError(kRecorderProcess, std::string("--db: ") + e.what());
        return 2;
    }
    try {
        gyrocal::process::InstallStopHandlers();
        gyrocal::recorder::node::RecorderNode node(o, std::move(writer));
        return node.Run();
    } catch (const std::exception& e) {
        gyrocal::process::PrintError(kRecorderProcess, e.what());
        return 1;
    }
}
