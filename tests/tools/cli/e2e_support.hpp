#pragma once
// What the end-to-end tests of `gyrocal` share: a scratch folder per test, the UDP multicast URL
// of a test's own port, and minimal read-only SQL for the checks (the store's own library is
// tested in tests/store): rows as text, one text, integer or real.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocal {

// An empty folder `name`_<pid> under GoogleTest's temp folder (what an earlier run left removed).
inline std::string FreshDir(const std::string& name) {
    const std::string dir = ::testing::TempDir() + name + "_" + std::to_string(getpid());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// The multicast bus on `port`: TTL 0 keeps it on this host (1: the namespaces' bridge), with the
// 4 MB receive buffer every gyrocal process asks for.
inline std::string UdpmUrl(int port, int ttl = 0) {
    return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=" + std::to_string(ttl) +
           "&recv_buf_size=4194304";
}

// The `gyrocal calibrate` arguments every simulated end-to-end run gives: `sensors` units drawn
// with `seed`, at `speed` times real time, stored in `db`, on the bus `url`, the logs (and the
// rig's truth.json) in `log_dir`, no progress lines.
inline std::vector<std::string> SimRunArgs(const std::string& sensors, const std::string& seed,
                                           const std::string& speed, const std::string& db,
                                           const std::string& url, const std::string& log_dir) {
    return {"--sensors", sensors,     "--seed", seed,        "--speed", speed,    "--db",
            db,          "--lcm-url", url,      "--log-dir", log_dir,   "--quiet"};
}

// Fast thermal constants that keep a simulated run short: the package lag 40 s, the chamber and
// the sequencer ramping at 10 degC/min.
inline const std::vector<std::string> kFastThermalArgs = {
    "--rig-arg=--package-tau-s=40", "--rig-arg=--ramp-c-per-min=10",
    "--sequencer-arg=--ramp-rate-c-per-min=10"};

// The pieces of a command line, in order, as one.
inline std::vector<std::string> Joined(std::initializer_list<std::vector<std::string>> pieces) {
    std::vector<std::string> all;
    for (const std::vector<std::string>& p : pieces) all.insert(all.end(), p.begin(), p.end());
    return all;
}

// A simulated run made for `gyrocal analyze` to find the one effect a test switches on: one unit
// drawn with `seed` at 30 times real time (the rest as SimRunArgs), the fast thermal constants
// (~1 simulated hour), and the temperature sensor's lag made negligible (0.1 s) so that the
// declared model lacks nothing else (with the rig's default 15 s lag the offset follows dT/dt and
// the analysis rightly finds temp_rate as well); 500 s of wall time at most.
inline std::vector<std::string> OneEffectRunArgs(const std::string& seed, const std::string& db,
                                                 const std::string& url,
                                                 const std::string& log_dir) {
    return Joined({SimRunArgs("1", seed, "30", db, url, log_dir),
                   kFastThermalArgs,
                   {"--rig-arg=--sensor-tau-s=0.1", "--wall-timeout-s", "500"}});
}

// Per sensor of `run`: sensor_id, its gyro samples stored, the span of their seq (max - min + 1),
// and the gaps the recorder counted on its GYRO_ channel (NULL when it has no losses row).
inline std::string GyroStreamsSql(const std::string& run) {
    return "SELECT g.sensor_id, count(*), max(seq) - min(seq) + 1, (SELECT seq_gaps FROM losses l "
           "WHERE l.run_id = g.run_id AND l.channel = 'GYRO_' || g.sensor_id) FROM gyro_samples g "
           "WHERE run_id = '" +
           run + "' GROUP BY g.sensor_id";
}

class Sql {
public:
    explicit Sql(const std::string& path) {
        if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
            throw std::runtime_error("cannot open " + path);
        sqlite3_busy_timeout(db_, 5000);
    }
    ~Sql() { sqlite3_close(db_); }
    Sql(const Sql&) = delete;
    Sql& operator=(const Sql&) = delete;
    std::vector<std::vector<std::string>> Rows(const std::string& sql) {
        sqlite3_stmt* st = nullptr;
        if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK)
            throw std::runtime_error(std::string("bad SQL: ") + sqlite3_errmsg(db_) + ": " + sql);
        std::vector<std::vector<std::string>> out;
        while (sqlite3_step(st) == SQLITE_ROW) {
            std::vector<std::string> row;
            for (int i = 0; i < sqlite3_column_count(st); ++i) {
                const unsigned char* t = sqlite3_column_text(st, i);
                row.push_back(t ? reinterpret_cast<const char*>(t) : "");
            }
            out.push_back(row);
        }
        sqlite3_finalize(st);
        return out;
    }
    // The first column of the first row: as text ("" when there is no row), an integer, a real.
    std::string Text(const std::string& sql) {
        const auto rows = Rows(sql);
        return rows.empty() || rows[0].empty() ? "" : rows[0][0];
    }
    int64_t Int(const std::string& sql) { return std::stoll(Rows(sql).at(0).at(0)); }
    double Real(const std::string& sql) { return std::stod(Rows(sql).at(0).at(0)); }
    // ATTACH another file read-only under `name`, to compare two databases in one query.
    void Attach(const std::string& path, const std::string& name) {
        Rows("ATTACH '" + path + "' AS " + name);
    }

private:
    sqlite3* db_ = nullptr;
};

}  // namespace gyrocal
