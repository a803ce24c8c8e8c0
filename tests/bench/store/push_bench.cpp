// Benchmark of the lab's central database (not a test; prints figures, asserts nothing):
//   A. `gyrocal push` of one run of N gyro samples (default 1.5 million: 4 units x 375 000, an hour
//      at 100 Hz each, with the run's encoder, chamber, rate and other rows; tests/store/
//      station_fixture.hpp) into a throwaway PostgreSQL server on this machine with fsync on (a
//      real server's durability): wall time, samples/s and rows/s, the pusher's CPU, and the time
//      to read the same rows from the station file alone (what the push cannot beat);
//   B. `gyrocal history UNIT` (query and table) over a centre of R runs (default 1000) of U units
//      (default 100; each run calibrates 10 of them, so each unit has R/10 runs), against the
//      same query on the station's SQLite file.
// Usage: push_bench [SAMPLES [RUNS [UNITS]]]. The server runs on the same 2 cores as the pusher.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <vector>

#include "store/db/central_db.hpp"
#include "store/db/push.hpp"
#include "store/db/push_tables.hpp"
#include "store/db/query.hpp"
#include "store/format/format.hpp"
#include "tests/bench/support/bench_args.hpp"
#include "tests/bench/support/bench_context.hpp"
#include "tests/bench/support/machine.hpp"
#include "tests/store/pg_server.hpp"
#include "tests/store/scratch_db.hpp"
#include "tests/store/station_fixture.hpp"

namespace {

namespace st = gyrocal::db;
namespace tg = gyrocal::testing;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double CpuSeconds() { return gyrocal::bench::ReadProcStats(getpid()).cpu_s; }

// Reading every row from the station file (it holds the one run), as the push reads them, with
// every value read as text (no sending): what the push cannot beat.
double ReadStationOnly(const std::string& station, int64_t* rows) {
    auto db = st::OpenForQuery(station);
    const auto t0 = Clock::now();
    *rows = 0;
    for (const auto& t : st::push::StationTables(*db)) {
        if (t.scope == st::push::Scope::kLocal) continue;
        std::string cols;
        for (const auto& c : t.columns) cols += (cols.empty() ? "" : ", ") + c.name;
        st::Stmt s(*db, "SELECT rowid, " + cols + " FROM " + t.name + " ORDER BY rowid");
        while (s.Step()) {
            for (int i = 1; i <= static_cast<int>(t.columns.size()); ++i) (void)s.Text(i);
            ++*rows;
        }
    }
    return Since(t0);
}

void PartA(tg::PgServer& server, int64_t samples) {
    const std::string station = tg::FreshDbPath("push_bench_station");
    tg::StationSpec spec{.prefix = "BENCH",
                         .sensors = {"U1", "U2", "U3", "U4"},
                         .runs = 1,
                         .samples_per_sensor = samples / 4};
    const auto w0 = Clock::now();
    tg::WriteStation(station, spec);
    std::printf("station file written in %.1f s (%s)\n", Since(w0), station.c_str());
    int64_t read_rows = 0;
    const double read_s = ReadStationOnly(station, &read_rows);
    const std::string url = server.Url(server.NewDatabase("bench_push"));
    st::InitCentral(url);
    st::PushOptions o;
    o.station_db = station;
    o.central_url = url;
    o.software_version = "bench";
    const double cpu0 = CpuSeconds();
    const auto t0 = Clock::now();
    const st::PushReport r = st::Push(o);
    const double wall = Since(t0), cpu = CpuSeconds() - cpu0;
    const st::RunPush& p = r.runs.at(0);
    std::printf("\nA. push of one run: %lld gyro samples, %lld rows in all\n",
                static_cast<long long>(p.samples_added), static_cast<long long>(p.rows_added));
    std::printf("| what | s | gyro samples/s | rows/s |\n|---|---|---|---|\n");
    std::printf("| gyrocal push (one transaction, COPY) | %.2f | %.0f | %.0f |\n", wall,
                p.samples_added / wall, p.rows_added / wall);
    std::printf("| reading the same rows from the station file only | %.2f | - | %.0f |\n", read_s,
                read_rows / read_s);
    std::printf(
        "pusher CPU %.2f s (%.0f %% of the wall time); the rest is the server (same "
        "machine) and waiting on it\n",
        cpu, 100 * cpu / wall);
    const auto t1 = Clock::now();
    st::Push(o);
    std::printf("a second push of the same run (nothing new): %.2f s\n", Since(t1));
    std::filesystem::remove(station);
}

// A station of `runs` runs, each calibrating 10 of `units` units (a final and a superseded set).
void WriteManyRuns(const std::string& path, int runs, int units) {
    st::StoreWriter w(path, {"bench", "bench-host", 1});
    const int64_t t0 = 1767225600LL * 1000000LL;
    for (int k = 0; k < runs; ++k) {
        const std::string run = "H-R" + std::to_string(k);
        std::vector<std::string> ids;
        for (int i = 0; i < 10; ++i) ids.push_back("U" + std::to_string((k * 10 + i) % units));
        std::vector<st::Row> rows;
        const int64_t t = t0 + k * 3600LL * 1000000LL;
        rows.push_back(tg::RunEvent(run, "start", ids, t));
        for (const std::string& id : ids) {
            for (int v = 1; v <= 2; ++v) {
                st::CoeffSetRow c;
                c.run_id = run;
                c.sensor_id = id;
                c.source = "fitter";
                c.coeff_set_id = v;
                c.utime = v;
                c.offset = tg::StationModel("offset_v", {2.5 + 1e-4 * k, 1e-3, -2e-6});
                c.sensitivity = tg::StationModel("sensitivity_v_per_dps", {0.0067, 1e-6});
                c.plateau_ids = {1, 2, 3};
                c.rotation_ids = {1, 2};
                c.recv_utime = t + v;
                rows.push_back(c);
            }
        }
        rows.push_back(tg::RunEvent(run, "stop", ids, t + 10));
        w.Write(rows, {});
    }
}

// Median wall time of `n` runs of open + history query + table.
double HistoryTime(const std::string& db_name, const std::string& unit, int n, size_t* sets) {
    std::vector<double> times;
    for (int i = 0; i < n; ++i) {
        const auto t0 = Clock::now();
        auto db = st::OpenForQuery(db_name);
        const auto h = st::SensorHistory(*db, unit, true);
        const std::string text = gyrocal::format::HistoryTable(unit, h, {0, 25, 50});
        times.push_back(Since(t0));
        *sets = h.size();
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

void PartB(tg::PgServer& server, int runs, int units) {
    const std::string station = tg::FreshDbPath("push_bench_history");
    WriteManyRuns(station, runs, units);
    const std::string url = server.Url(server.NewDatabase("bench_history"));
    st::InitCentral(url);
    st::PushOptions o;
    o.station_db = station;
    o.central_url = url;
    const auto t0 = Clock::now();
    const st::PushReport r = st::Push(o);
    const double push_s = Since(t0);
    size_t sets = 0;
    const double centre = HistoryTime(url, "U42", 5, &sets);
    const double file = HistoryTime(station, "U42", 5, &sets);
    std::printf("\nB. %d runs x 10 of %d units (%zu runs pushed in %.1f s, %.1f runs/s)\n", runs,
                units, r.runs.size(), push_s, r.runs.size() / push_s);
    std::printf("| gyrocal history U42 (final sets: %zu) | median of 5 [ms] |\n|---|---|\n", sets);
    std::printf("| central PostgreSQL | %.1f |\n| station SQLite file | %.1f |\n", centre * 1e3,
                file * 1e3);
    if (!std::getenv("GYROCAL_BENCH_KEEP")) std::filesystem::remove(station);
}

}  // namespace

int main(int argc, char** argv) {
    const int64_t samples = gyrocal::bench::IntArg(argc, argv, 1, 1'500'000);
    const int runs = gyrocal::bench::IntArg(argc, argv, 2, 1000);
    const int units = gyrocal::bench::IntArg(argc, argv, 3, 100);
    if (samples < 4 || runs < 1 || units < 10)
        return gyrocal::bench::Usage(argv, "[SAMPLES [RUNS [UNITS]]]");
    gyrocal::bench::PrintContext(argc, argv);
    char tmpl[] = "/tmp/gyrocal-pg-bench-XXXXXX";
    if (mkdtemp(tmpl) == nullptr) return 1;
    try {
        auto server = tg::PgServer::Start(tmpl, true);
        PartA(*server, samples);
        PartB(*server, runs, units);
        std::printf("load after: %s\n", gyrocal::bench::LoadAverage().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "push_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
