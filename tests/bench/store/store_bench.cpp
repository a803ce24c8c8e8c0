// Store and recorder throughput (a benchmark, not a test): prints tables and the machine.
//  A. Insert rate of the store alone: bare SQLite (one table, no index, prepared, 1000 rows per
//     transaction) = what SQLite can do here; StoreWriter::Write (the real schema and index);
//     AsyncWriter (queue + writer thread) end to end.
//  B. gyrocal-recorder and lcm-logger side by side on the same multicast stream of gyro samples
//     (units x rate, rising), each step a fresh database/log: messages each one stored, loss,
//     CPU and peak memory. Rises until the recorder loses (then one more step), until the
//     publisher cannot reach the target twice, or to the last step.
//  C. A sustained run at a fixed rate: the recorder's resident memory over time (must be flat).
//  A2. What a rates(run_id, sensor_id, utime) index would cost on the recorder's gyro + rate mix.
// Options: --step-s S (default 3), --long-s S (default 30), --port P (default 7779), --keep
// (keep the temporary databases and logs), --store-only (parts A and A2 only).
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "store/db/async_writer.hpp"
#include "store/db/sqlite_db.hpp"
#include "store/db/writer.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/bench/support/machine.hpp"
#include "tests/store/row_builders.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
namespace st = gyrocal::db;
using gyrocal::bench::ProcStats;
using gyrocal::bench::ReadProcStats;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

std::string TempDir() {
    const auto d = std::filesystem::temp_directory_path() /
                   ("gyrocal_store_bench_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}

void Remove(const std::string& p) {
    for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(p + ext);
}

// The i-th sample of the bench stream: a unit at rest (its output moving a little), 16 sensors
// in turn, 1 ms apart, received at i.
st::GyroRow Row(int64_t i) {
    st::GyroRow g = gyrocal::testing::GyroSample("BENCH", "S" + std::to_string(i % 16), i / 16,
                                                 1000000000000000 + i * 1000, i);
    g.gyro_v += 1e-6 * static_cast<double>(i % 1000);
    g.temp_v = 2.5;
    return g;
}

// The compensated rate of sample `g`, stored beside it.
st::RateRow RateRowOf(const st::GyroRow& g) {
    return {.run_id = g.run_id,
            .sensor_id = g.sensor_id,
            .utime = g.utime,
            .seq = g.seq,
            .rate_dps = 0.01,
            .angle_deg = 1.0,
            .temp_c = g.temp_c,
            .coeff_set_id = 7,
            .recv_utime = g.recv_utime};
}

// What a rates(run_id, sensor_id, utime) index would cost: the recorder's real mix (each gyro
// sample has its compensated rate), with the current schema and with that index added. (This
// measurement is why schema v4 does not have it.)
void RatesIndexCost(const std::string& dir) {
    constexpr int64_t kSamples = 150000, kBatch = 500;  // 1000 rows per transaction
    std::printf(
        "\nA2. Cost of a rates(run_id, sensor_id, utime) index (%lld gyro + %lld rate "
        "rows, 1000 per transaction; 3 repeats each, alternating)\n",
        static_cast<long long>(kSamples), static_cast<long long>(kSamples));
    std::printf("%-52s %12s %12s %12s\n", "path", "rows/s #1", "rows/s #2", "rows/s #3");
    double rate[2][3] = {};
    for (int rep = 0; rep < 3; ++rep) {
        for (int with_index = 1; with_index >= 0; --with_index) {
            const std::string p = dir + "/rates" + std::to_string(with_index) + ".db";
            Remove(p);
            st::StoreWriter w(p, {"bench", "h", 1});
            if (with_index) {
                w.db().Exec(
                    "CREATE INDEX rates_run_sensor_utime ON rates(run_id, sensor_id, utime)");
            }
            const auto t0 = Clock::now();
            std::vector<st::Row> batch;
            for (int64_t b = 0; b < kSamples / kBatch; ++b) {
                batch.clear();
                for (int64_t k = 0; k < kBatch; ++k) {
                    const st::GyroRow g = Row(b * kBatch + k);
                    batch.push_back(g);
                    batch.push_back(RateRowOf(g));
                }
                w.Write(batch, {});
            }
            rate[with_index][rep] = 2.0 * kSamples / Seconds(Clock::now() - t0);
        }
    }
    for (int with_index = 1; with_index >= 0; --with_index) {
        std::printf("%-52s %12.0f %12.0f %12.0f\n",
                    with_index ? "StoreWriter: gyro + rates, rates index added"
                               : "StoreWriter: gyro + rates, schema v4 (no rates index)",
                    rate[with_index][0], rate[with_index][1], rate[with_index][2]);
    }
}

void StoreAlone(const std::string& dir) {
    constexpr int64_t kRows = 300000, kBatch = 1000;
    std::printf("\nA. Insert rate of the store alone (%lld gyro rows, %lld per transaction)\n",
                static_cast<long long>(kRows), static_cast<long long>(kBatch));
    std::printf("%-52s %12s\n", "path", "rows/s");
    {
        const std::string p = dir + "/bare.db";
        Remove(p);
        st::Db db(p, st::Db::Mode::kReadWriteCreate);
        db.Exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;");
        db.Exec(
            "CREATE TABLE g(run_id TEXT, sensor_id TEXT, utime INTEGER, seq INTEGER, gyro_v "
            "REAL, temp_v REAL, temp_c REAL, supply_v REAL, has_adc INTEGER, gyro_counts "
            "INTEGER, temp_counts INTEGER, supply_counts INTEGER, recv_utime INTEGER)");
        st::Stmt ins(db, "INSERT INTO g VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)");
        const auto t0 = Clock::now();
        for (int64_t b = 0; b < kRows / kBatch; ++b) {
            st::Transaction tx(db);
            for (int64_t k = 0; k < kBatch; ++k) {
                const st::GyroRow r = Row(b * kBatch + k);
                ins.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.utime).Bind(4, r.seq);
                ins.Bind(5, r.gyro_v).Bind(6, r.temp_v).Bind(7, r.temp_c).Bind(8, r.supply_v);
                ins.Bind(9, 0).Bind(13, r.recv_utime).Run();
            }
            tx.Commit();
        }
        std::printf("%-52s %12.0f\n", "bare SQLite: 1 table, no index, prepared",
                    kRows / Seconds(Clock::now() - t0));
    }
    {
        const std::string p = dir + "/writer.db";
        Remove(p);
        st::StoreWriter w(p, {"bench", "h", 1});
        const auto t0 = Clock::now();
        std::vector<st::Row> batch;
        for (int64_t b = 0; b < kRows / kBatch; ++b) {
            batch.clear();
            for (int64_t k = 0; k < kBatch; ++k) batch.push_back(Row(b * kBatch + k));
            w.Write(batch, {});
        }
        std::printf("%-52s %12.0f\n", "StoreWriter::Write (gyrocal schema, block index)",
                    kRows / Seconds(Clock::now() - t0));
    }
    {
        const std::string p = dir + "/async.db";
        Remove(p);
        st::StoreWriter w(p, {"bench", "h", 1});
        st::AsyncWriter aw(w, {static_cast<size_t>(kRows) + 1, 1000, 200ms});
        const std::string ch = "GYRO_S0";
        const auto t0 = Clock::now();
        for (int64_t i = 0; i < kRows; ++i) aw.Push(Row(i), ch);
        aw.Stop();
        std::printf("%-52s %12.0f\n", "AsyncWriter: push from one thread until committed",
                    kRows / Seconds(Clock::now() - t0));
    }
}

int64_t CountRows(const std::string& db);

// Drain: until the recorder stored `published` rows, or its count stopped moving for 2 s
// (bounded at 30 s); a loaded machine can starve a process for a while.
void WaitForDrain(const std::string& db, int64_t published) {
    int64_t last = -1;
    auto still_since = Clock::now();
    gyrocal::testing::WaitUntil(
        [&] {
            const int64_t n = CountRows(db);
            if (n >= published) return true;
            if (n != last) {
                last = n;
                still_since = Clock::now();
            }
            return Clock::now() - still_since > 2s;
        },
        30s, 100ms);
}

int64_t CountRows(const std::string& db) {
    try {
        st::Db d(db, st::Db::Mode::kReadOnly);
        st::Stmt s(d, "SELECT count(*) FROM gyro_samples");
        return s.Step() ? s.Int(0) : 0;
    } catch (...) {
        return 0;
    }
}

int64_t CountLogGyro(const std::string& path) {
    lcm::LogFile log(path, "r");
    if (!log.good()) return 0;
    int64_t n = 0;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
        if (e->channel.rfind("GYRO_", 0) == 0) ++n;
    }
    return n;
}

// Publishes `units` sensors at `hz` each for `seconds`; returns the count actually published.
int64_t Publish(gyrocal::bus::Bus& bus, int units, double hz, double seconds) {
    std::vector<gyrocal::gyro_sample_t> msgs(static_cast<size_t>(units));
    std::vector<std::string> chans;
    for (int u = 0; u < units; ++u) {
        auto& m = msgs[static_cast<size_t>(u)];
        m.sensor_id = "U" + std::to_string(u);
        m.gyro_v = 2.5;
        m.temp_v = 2.5;
        m.temp_c = 25;
        m.supply_v = std::nan("");
        m.supply_counts = -1;
        chans.push_back(gyrocal::channels::Gyro(m.sensor_id));
    }
    const double rate = units * hz;
    const int64_t total = static_cast<int64_t>(rate * seconds);
    const auto t0 = Clock::now();
    int64_t sent = 0;
    while (sent < total) {
        const int64_t due =
            std::min<int64_t>(total, static_cast<int64_t>(rate * Seconds(Clock::now() - t0)) + 1);
        while (sent < due) {
            const size_t u = static_cast<size_t>(sent % units);
            auto& m = msgs[u];
            m.utime =
                1000000000000000 + static_cast<int64_t>(static_cast<double>(m.seq) * 1e6 / hz);
            bus.Publish(chans[u], m);
            ++m.seq;
            ++sent;
        }
        // Time itself: the publisher keeps the stated rate (units x hz), sending what is due.
        std::this_thread::sleep_for(100us);
    }
    return bus.counters().published;
}

struct StepResult {
    int units = 0;
    double hz = 0;
    double achieved_rate = 0;
    int64_t published = 0, rec_stored = 0, log_stored = 0;
    int64_t rec_seq_gaps = 0, rec_queue_drops = 0;  // the recorder's own accounting
    double rec_cpu_pct = 0, log_cpu_pct = 0;
    int64_t rec_hwm_kb = 0, log_hwm_kb = 0;
};

bool WaitForRecorder(gyrocal::bus::Bus& bus, pid_t pid) {
    bool seen = false;
    bus.Subscribe<gyrocal::status_t>("STATUS", [&](const gyrocal::status_t& s, const std::string&) {
        if (s.pid == pid) seen = true;
    });
    const auto end = Clock::now() + 10s;
    while (!seen && Clock::now() < end) bus.Handle(50ms);
    return seen;
}

StepResult Step(const std::string& dir, const std::string& url, int units, double hz,
                double seconds) {
    StepResult r;
    r.units = units;
    r.hz = hz;
    const std::string db = dir + "/step.db", log = dir + "/step.lcmlog";
    Remove(db);
    std::filesystem::remove(log);
    gyrocal::bus::Bus bus(gyrocal::bus::BusOptions{url});
    gyrocal::launch::ChildProcess rec(
        {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db", db, "--lcm-url", url}, "",
        dir + "/rec.err");
    gyrocal::launch::ChildProcess logger({"lcm-logger", "-q", "-f", "--lcm-url=" + url, log}, "",
                                         dir + "/logger.err");
    if (!WaitForRecorder(bus, rec.pid())) {
        std::cerr << "recorder did not start\n";
        return r;
    }
    // lcm-logger has no heartbeat: ping on a side channel until its file grows (it flushes
    // every 100 ms), so both listen before the stream starts.
    const uint8_t ping[8] = {0};
    gyrocal::testing::WaitUntil(
        [&] {
            if (std::filesystem::exists(log) && std::filesystem::file_size(log) > 0) return true;
            bus.PublishRaw("BENCH_PING", ping, sizeof ping);
            return false;
        },
        10s, 50ms);
    const int64_t pings = bus.counters().published;
    const ProcStats rec0 = ReadProcStats(rec.pid()), log0 = ReadProcStats(logger.pid());
    const auto t0 = Clock::now();
    r.published = Publish(bus, units, hz, seconds) - pings;
    r.achieved_rate = r.published / Seconds(Clock::now() - t0);
    WaitForDrain(db, r.published);
    const double wall = Seconds(Clock::now() - t0);
    const ProcStats rec1 = ReadProcStats(rec.pid()), log1 = ReadProcStats(logger.pid());
    r.rec_cpu_pct = 100 * (rec1.cpu_s - rec0.cpu_s) / wall;
    r.log_cpu_pct = 100 * (log1.cpu_s - log0.cpu_s) / wall;
    r.rec_hwm_kb = rec1.hwm_kb;
    r.log_hwm_kb = log1.hwm_kb;
    logger.Signal(SIGINT);
    logger.Wait(10s);
    rec.Stop(10s);
    r.rec_stored = CountRows(db);
    try {
        st::Db d(db, st::Db::Mode::kReadOnly);
        st::Stmt s(d,
                   "SELECT coalesce(sum(seq_gaps), 0), coalesce(sum(queue_drops), 0) FROM losses");
        if (s.Step()) {
            r.rec_seq_gaps = s.Int(0);
            r.rec_queue_drops = s.Int(1);
        }
    } catch (...) {
    }
    r.log_stored = CountLogGyro(log);
    return r;
}

void SideBySide(const std::string& dir, const std::string& url, double step_s) {
    std::printf(
        "\nB. gyrocal-recorder vs lcm-logger on the same stream (gyro_sample_t, %.0f s per step)\n",
        step_s);
    std::printf("%6s %6s %10s %10s | %10s %8s %8s %8s %6s %6s | %10s %8s %6s %6s\n", "units", "hz",
                "target/s", "sent/s", "rec stored", "rec lost", "gaps", "qdrops", "rec%", "recMB",
                "log stored", "log lost", "log%", "logMB");
    const std::vector<std::pair<int, double>> steps = {{8, 100},    {16, 500},  {32, 1000},
                                                       {64, 1000},  {96, 1000}, {128, 1000},
                                                       {192, 1000}, {256, 1000}};
    int after_loss = -1, publisher_short = 0;
    for (const auto& [units, hz] : steps) {
        const StepResult r = Step(dir, url, units, hz, step_s);
        const int64_t rec_lost = r.published - r.rec_stored, log_lost = r.published - r.log_stored;
        std::printf(
            "%6d %6.0f %10.0f %10.0f | %10lld %8lld %8lld %8lld %6.0f %6.1f | %10lld %8lld "
            "%6.0f %6.1f\n",
            units, hz, units * hz, r.achieved_rate, static_cast<long long>(r.rec_stored),
            static_cast<long long>(rec_lost), static_cast<long long>(r.rec_seq_gaps),
            static_cast<long long>(r.rec_queue_drops), r.rec_cpu_pct, r.rec_hwm_kb / 1024.0,
            static_cast<long long>(r.log_stored), static_cast<long long>(log_lost), r.log_cpu_pct,
            r.log_hwm_kb / 1024.0);
        std::fflush(stdout);
        // Rising until the recorder loses too (lcm-logger loses first here), then one more step;
        // also stop when the publisher itself cannot reach the target twice.
        if (after_loss < 0 && rec_lost > 0) after_loss = 0;
        if (after_loss >= 0 && ++after_loss > 1) break;
        if (r.achieved_rate < 0.9 * units * hz && ++publisher_short >= 2) break;
    }
    std::printf(
        "(lost = published - stored; gaps/qdrops = the recorder's own loss accounting in its "
        "database: seq gaps seen, own queue drops; rec%%/log%% = CPU of one core over "
        "publish+drain; MB = peak resident)\n");
}

void LongRun(const std::string& dir, const std::string& url, double seconds) {
    const int units = 32;
    const double hz = 1000;
    std::printf("\nC. Sustained %d units x %.0f Hz for %.0f s: recorder resident memory\n", units,
                hz, seconds);
    const std::string db = dir + "/long.db";
    Remove(db);
    gyrocal::bus::Bus bus(gyrocal::bus::BusOptions{url});
    gyrocal::launch::ChildProcess rec(
        {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db", db, "--lcm-url", url}, "",
        dir + "/long.err");
    if (!WaitForRecorder(bus, rec.pid())) return;
    std::atomic<bool> done{false};
    std::vector<std::pair<double, int64_t>> rss;
    std::thread sampler([&] {
        const auto t0 = Clock::now();
        while (!done) {
            rss.emplace_back(Seconds(Clock::now() - t0), ReadProcStats(rec.pid()).rss_kb);
            std::this_thread::sleep_for(2s);  // time itself: the sampling period
        }
    });
    const int64_t sent = Publish(bus, units, hz, seconds);
    done = true;
    sampler.join();
    WaitForDrain(db, sent);
    const ProcStats end = ReadProcStats(rec.pid());
    rec.Stop(10s);
    int64_t gaps = 0, drops = 0;
    {
        st::Db d(db, st::Db::Mode::kReadOnly);
        st::Stmt s(d,
                   "SELECT coalesce(sum(seq_gaps), 0), coalesce(sum(queue_drops), 0) FROM losses");
        if (s.Step()) {
            gaps = s.Int(0);
            drops = s.Int(1);
        }
    }
    std::printf("%8s %10s\n", "t_s", "rss_MB");
    for (const auto& [t, kb] : rss) std::printf("%8.0f %10.1f\n", t, kb / 1024.0);
    std::printf(
        "sent %lld, stored %lld (recorder's accounting: %lld seq gaps, %lld queue drops), "
        "peak resident %.1f MB\n",
        static_cast<long long>(sent), static_cast<long long>(CountRows(db)),
        static_cast<long long>(gaps), static_cast<long long>(drops), end.hwm_kb / 1024.0);
}

}  // namespace

int main(int argc, char** argv) {
    double step_s = 3, long_s = 30;
    int port = 7779;
    bool keep = false;
    bool store_only = false;  // part A only (no processes, no multicast)
    for (int i = 1; i < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--keep") {
            keep = true;
            --i;
            continue;
        }
        if (a == "--store-only") {
            store_only = true;
            --i;
            continue;
        }
        if (i + 1 >= argc) {
            std::cerr << "store_bench: " << a << " needs a value\n";
            return 2;
        }
        if (a == "--step-s")
            step_s = std::stod(argv[i + 1]);
        else if (a == "--long-s")
            long_s = std::stod(argv[i + 1]);
        else if (a == "--port")
            port = std::stoi(argv[i + 1]);
        else {
            std::cerr << "store_bench: unknown option " << a
                      << " (valid: --step-s S, --long-s S, --port P, --keep, --store-only)\n";
            return 2;
        }
    }
    const std::string url =
        "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304";
    gyrocal::bench::PrintContext(argc, argv);
    std::printf("SQLite %s\n", sqlite3_libversion());
    const std::string dir = TempDir();
    StoreAlone(dir);
    RatesIndexCost(dir);
    if (!store_only) {
        SideBySide(dir, url, step_s);
        if (long_s > 0) LongRun(dir, url, long_s);
    }
    if (keep) {
        std::printf("kept %s\n", dir.c_str());
    } else {
        std::filesystem::remove_all(dir);
    }
    return 0;
}
