// How fast the real process graph of `gyrocal calibrate` runs, and what limits it: runs the
// command given after `--` (the launcher and every process it starts, on a real LCM multicast
// group), samples each process's CPU time and resident memory from /proc while it runs
// (--sample-ms), then reads the run's database: samples stored, losses, and every process's
// datagrams published (its last STATUS). Prints, per process, the CPU it spent per datagram on
// the group (every process receives every datagram) and per gyro sample, its peak memory and
// how much its memory grew after the first --from of the run; and the capacity those costs
// allow: nproc / (sum of CPU per sample). --load N runs N CPU-bound busy loops beside it.
// Not a test: figures, after the header block of every benchmark (date, commit, machine, load).
//
// Run: build/bin/gyrocal_bench_graph [--load N] [--sample-ms MS] [--from F] [--rss-out FILE]
//          -- --source csv --input day.csv --db /tmp/bench.db
#include <sqlite3.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "tests/bench/graph/proc_sampler.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/bench/support/machine.hpp"

namespace {

using namespace gyrocal;
using namespace gyrocal::bench;

struct Args {
    int load = 0;
    int sample_ms = 500;
    double from = 1.0 / 6.0;  // the first 4 h of a 24 h run
    std::string rss_out;      // every sample: t, pid, name, RSS
    std::vector<std::string> calibrate;
    std::string db;
};

Args Parse(int argc, char** argv) {
    Args a;
    int i = 1;
    for (; i < argc && std::string(argv[i]) != "--"; ++i) {
        const std::string k = argv[i];
        const std::string v = i + 1 < argc ? argv[i + 1] : "";
        if (k == "--load")
            a.load = std::stoi(v), ++i;
        else if (k == "--sample-ms")
            a.sample_ms = std::stoi(v), ++i;
        else if (k == "--from")
            a.from = std::stod(v), ++i;
        else if (k == "--rss-out")
            a.rss_out = v, ++i;
        else
            throw std::invalid_argument("unknown option " + k + " (options come before --)");
    }
    for (++i; i < argc; ++i) a.calibrate.push_back(argv[i]);
    for (size_t j = 0; j + 1 < a.calibrate.size(); ++j)
        if (a.calibrate[j] == "--db") a.db = a.calibrate[j + 1];
    if (a.db.empty()) {
        a.db = (std::filesystem::temp_directory_path() /
                ("gyrocal_bench_graph_" + std::to_string(getpid()) + ".db"))
                   .string();
        a.calibrate.insert(a.calibrate.end(), {"--db", a.db});
    }
    return a;
}

// One-row integer queries on the run's database.
struct Db {
    sqlite3* db = nullptr;
    explicit Db(const std::string& path) {
        if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
            throw std::runtime_error("cannot open " + path);
    }
    ~Db() { sqlite3_close(db); }
    template <class Row>
    void Each(const std::string& sql, const std::string& bind, Row&& row) {
        sqlite3_stmt* st = nullptr;
        if (sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr) != SQLITE_OK)
            throw std::runtime_error(sql + ": " + sqlite3_errmsg(db));
        if (!bind.empty()) sqlite3_bind_text(st, 1, bind.c_str(), -1, SQLITE_TRANSIENT);
        while (sqlite3_step(st) == SQLITE_ROW) row(st);
        sqlite3_finalize(st);
    }
    int64_t Int(const std::string& sql, const std::string& bind = "") {
        int64_t v = 0;
        Each(sql, bind, [&](sqlite3_stmt* st) { v = sqlite3_column_int64(st, 0); });
        return v;
    }
    std::string Text(const std::string& sql) {
        std::string v;
        Each(sql, "", [&](sqlite3_stmt* st) {
            if (const unsigned char* t = sqlite3_column_text(st, 0))
                v = reinterpret_cast<const char*>(t);
        });
        return v;
    }
};

// Every process's datagrams published and the most sequence gaps it reported, by pid.
struct BusFigures {
    int64_t datagrams = 0;
    int64_t max_seq_gaps = 0;
    std::string worst;
};
BusFigures ReadBus(Db& db) {
    BusFigures f;
    db.Each("SELECT process, pid, MAX(published), MAX(seq_gaps) FROM status GROUP BY process, pid",
            "", [&](sqlite3_stmt* st) {
                f.datagrams += sqlite3_column_int64(st, 2);
                const int64_t gaps = sqlite3_column_int64(st, 3);
                if (gaps > f.max_seq_gaps) {
                    f.max_seq_gaps = gaps;
                    f.worst = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
                }
            });
    return f;
}

void PrintProcesses(const ProcSampler& sampler, double wall_s, int64_t datagrams, int64_t samples,
                    double from) {
    std::printf(
        "\n| process | pid | CPU [s] | CPU [%% of a core] | CPU per datagram on the group [us] | "
        "CPU per gyro sample [us] | peak RSS [MB] | RSS growth after %.0f %% of the run [MB] |\n",
        from * 100);
    std::printf("|---|---|---|---|---|---|---|---|\n");
    double sum_cpu = 0;
    for (const auto& [pid, tr] : sampler.traces()) {
        if (tr.name == "sh") continue;  // the --load jobs are not part of the graph
        const RssGrowth g = GrowthAfter(tr, from);
        sum_cpu += tr.cpu_s;
        std::printf(
            "| %s | %d | %.1f | %.0f | %.2f | %.2f | %.1f | %+.1f |\n", tr.name.c_str(), pid,
            tr.cpu_s, 100 * tr.cpu_s / wall_s, datagrams ? 1e6 * tr.cpu_s / datagrams : 0,
            samples ? 1e6 * tr.cpu_s / samples : 0, tr.hwm_kb / 1024.0, g.growth_kb() / 1024.0);
    }
    const double per_sample_us = samples ? 1e6 * sum_cpu / samples : 0;
    std::printf(
        "\nCPU of the whole graph: %.1f s = %.2f cores busy on average; %.2f us per gyro "
        "sample in all processes together\n",
        sum_cpu, sum_cpu / wall_s, per_sample_us);
    if (per_sample_us > 0)
        std::printf(
            "capacity those costs allow: %u cores / %.2f us = %.0f gyro samples/s (achieved "
            "%.0f/s)\n",
            Nproc(), per_sample_us, Nproc() * 1e6 / per_sample_us, samples / wall_s);
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    try {
        a = Parse(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gyrocal_bench_graph: %s\n", e.what());
        return 2;
    }
    PrintContext(argc, argv);
    std::printf("CPU-bound jobs beside: %d\n", a.load);
    std::vector<std::string> cmd = {GYROCAL_CLI_EXE, "calibrate"};
    cmd.insert(cmd.end(), a.calibrate.begin(), a.calibrate.end());
    std::string shown;
    for (size_t i = 1; i < cmd.size(); ++i) shown += " " + cmd[i];
    std::printf("command: gyrocal%s\n", shown.c_str());
    std::fflush(stdout);
    std::vector<launch::ChildProcess> hogs;
    for (int i = 0; i < a.load; ++i)
        hogs.emplace_back(std::vector<std::string>{"sh", "-c", "while :; do :; done"});
    const std::string log = a.db + ".calibrate.log";
    const auto t0 = std::chrono::steady_clock::now();
    launch::ChildProcess calibrate(cmd, log, log);
    ProcSampler sampler(calibrate.pid(), a.rss_out);
    std::optional<launch::ExitStatus> status;
    while (!(status = calibrate.Poll())) {
        sampler.Sample();
        // Time itself: the sampling period of the resource figures.
        std::this_thread::sleep_for(std::chrono::milliseconds(a.sample_ms));
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    hogs.clear();
    std::printf("gyrocal calibrate %s after %.1f s wall (log %s)\n", status->Describe().c_str(),
                wall_s, log.c_str());
    Db db(a.db);
    const std::string run =
        db.Text("SELECT run_id FROM run_events WHERE event = 'start' ORDER BY rowid DESC LIMIT 1");
    const int64_t gyro = db.Int("SELECT COUNT(*) FROM gyro_samples WHERE run_id = ?", run);
    const int64_t enc = db.Int("SELECT COUNT(*) FROM encoder_samples WHERE run_id = ?", run);
    const int64_t rates = db.Int("SELECT COUNT(*) FROM rates WHERE run_id = ?", run);
    const int64_t lost = db.Int(
        "SELECT COALESCE(SUM(seq_gaps + decode_errors + queue_drops), 0) FROM losses WHERE run_id "
        "= ?",
        run);
    const BusFigures bus = ReadBus(db);
    std::printf(
        "run %s: %lld gyro samples stored (%.0f per wall second), %lld encoder samples, %lld "
        "rates; losses recorded: %lld; most sequence gaps any process reported: %lld%s%s\n",
        run.c_str(), static_cast<long long>(gyro), gyro / wall_s, static_cast<long long>(enc),
        static_cast<long long>(rates), static_cast<long long>(lost),
        static_cast<long long>(bus.max_seq_gaps), bus.worst.empty() ? "" : " at ",
        bus.worst.c_str());
    std::printf(
        "datagrams on the group (every process's STATUS published, summed): %lld (%.0f per "
        "wall second); database %.1f MB\n",
        static_cast<long long>(bus.datagrams), bus.datagrams / wall_s,
        std::filesystem::file_size(a.db) / 1e6);
    PrintProcesses(sampler, wall_s, bus.datagrams, gyro, a.from);
    return status->exited ? status->code : 1;
}
