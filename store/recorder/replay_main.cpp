// gyrocal-replay: publishes a stored run back onto LCM (gyro, encoder and chamber samples and
// the run events) with its original timing, `--speed X` times faster, or `--max` as fast as
// possible, so that processors can run again on historic data. Single thread: read the next row
// (merged across tables by reception time), wait until its time, publish.
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <string>
#include <thread>

#include "bus/bus.hpp"
#include "bus/process_main.hpp"
#include "bus/shutdown.hpp"
#include "query.hpp"
#include "replay_reader.hpp"
#include "replay_source.hpp"

namespace {

constexpr const char* kProcess = "gyrocal-replay";

struct ReplayOptions {
    std::string db_path = "gyrocal.db";
    std::string run_id;
    std::string lcm_url;
    std::string as_run;  // "" = the stored run id
    double speed = 1.0;  // [1] recorded seconds per wall second
    bool max = false;    // no waiting at all
    static ReplayOptions Defaults() { return {}; }
};

int64_t RecvUtimeOf(const gyrocal::store::Row& row) {
    return std::visit([](const auto& r) { return r.recv_utime; }, row);
}

int Replay(const ReplayOptions& o) {
    auto db = gyrocal::store::OpenForQuery(o.db_path);
    gyrocal::store::ReplayReader reader(*db, o.run_id);
    gyrocal::Bus bus(gyrocal::BusOptions{o.lcm_url});
    gyrocal::InstallStopHandlers();
    const auto wall0 = std::chrono::steady_clock::now();
    int64_t recv0 = -1;
    int64_t published = 0;
    while (!gyrocal::StopRequested()) {
        std::optional<gyrocal::store::Row> row = reader.Next();
        if (!row) break;
        const int64_t recv = RecvUtimeOf(*row);
        if (recv0 < 0) recv0 = recv;
        if (!o.max) {
            const auto due = wall0 + std::chrono::microseconds(static_cast<int64_t>(
                                         static_cast<double>(recv - recv0) / o.speed));
            // Sleep in short steps so SIGINT is honoured during long gaps.
            while (!gyrocal::StopRequested() && std::chrono::steady_clock::now() < due) {
                std::this_thread::sleep_until(
                    std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(100)));
            }
        }
        if (auto* ev = std::get_if<gyrocal::store::RunEventRow>(&*row); ev && !o.as_run.empty()) {
            ev->run_id = o.as_run;
        }
        const auto msg = gyrocal::record::EncodeForReplay(*row);
        if (!msg) continue;
        if (bus.PublishRaw(msg->channel, msg->bytes.data(), static_cast<int>(msg->bytes.size()))) {
            ++published;
        }
    }
    std::cerr << kProcess << ": published " << published << " messages of run '" << o.run_id
              << "' (" << bus.counters().publish_errors << " publish errors)\n";
    return bus.counters().publish_errors == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    ReplayOptions o = ReplayOptions::Defaults();
    CLI::App app{
        "gyrocal-replay: publishes a stored run (GYRO_*, ENCODER, CHAMBER_STATE, RUN_EVENT) back\n"
        "onto LCM with its original reception timing.\n"
        "Exit codes: 0 done (or stopped by SIGINT/SIGTERM), 1 unknown run, database or LCM\n"
        "failure, 2 bad options.",
        "gyrocal-replay"};
    app.add_option("run", o.run_id, "run id to replay")->required();
    app.add_option("--db", o.db_path, "SQLite database file")->capture_default_str();
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default $GYROCAL_LCM_URL or udpm default)");
    app.add_option("--as-run", o.as_run,
                   "publish the run events under this run id instead (keeps a replay recorded "
                   "into the same database apart from the original)");
    auto* speed = app.add_option("--speed", o.speed, "recorded seconds per wall second")
                      ->check(CLI::Range(1e-3, 1e6))
                      ->capture_default_str();
    app.add_flag("--max", o.max, "publish as fast as possible (no timing)")->excludes(speed);
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, kProcess)) return *exit_code;
    try {
        return Replay(o);
    } catch (const std::exception& e) {
        std::cerr << kProcess << ": error: " << e.what() << "\n";
        return 1;
    }
}
