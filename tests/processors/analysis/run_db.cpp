#include "tests/processors/analysis/run_db.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "store/db/writer.hpp"
#include "tests/processors/analysis/sim_run.hpp"

namespace gyrocal::analysis::testing {

namespace st = gyrocal::db;

std::string WriteRunDb(const std::string& name) {
    SimRunOptions o;
    o.seed = 601;
    sim::SetEffect(o.effects, "hysteresis", 1e-3);
    return WriteRunDb(name, o);
}

std::string WriteRunDb(const std::string& name, const SimRunOptions& o) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("gyrocal_analysis_cli_" + std::to_string(::getpid()) + "_" + name))
                                 .string();
    std::filesystem::remove(path);
    WriteSimRun(path, "R1", MakeSimRun(o, true));
    return path;
}

namespace {

// A row of run `run_id` (of unit S01 where the row is about a unit) sent at `utime` [us] and
// received at once, as the recorder stores what it hears.
template <class Row>
Row RunRow(const std::string& run_id, int64_t utime) {
    Row r;
    r.run_id = run_id;
    if constexpr (requires { r.sensor_id; }) r.sensor_id = "S01";
    r.utime = utime;
    r.recv_utime = utime;
    return r;
}

}  // namespace

void WriteSimRun(const std::string& path, const std::string& run_id, const SimRun& s, int units) {
    auto unit = [](int k) { return "S0" + std::to_string(k + 1); };
    st::StoreWriter w(path, {"test", "host", 1});
    std::vector<st::Row> rows;
    st::RunEventRow start = RunRow<st::RunEventRow>(run_id, s.raw.front().utime);
    start.event = "start";
    for (int k = 0; k < units; ++k) start.sensor_ids.push_back(unit(k));
    start.setpoint_c = NAN;
    rows.push_back(start);
    for (const GyroSample& g : s.raw)
        for (int k = 0; k < units; ++k) {
            st::GyroRow r = RunRow<st::GyroRow>(run_id, g.utime);
            r.sensor_id = unit(k);
            r.seq = g.seq;
            r.gyro_v = g.gyro_v + 1e-3 * k;
            r.temp_c = g.temp_c;
            r.temp_v = NAN;
            r.supply_v = g.supply_v;
            rows.push_back(r);
        }
    int64_t seq = 0;
    for (const motion::EncoderReading& e : s.encoder) {
        st::EncoderRow r = RunRow<st::EncoderRow>(run_id, e.utime);
        r.encoder_id = "E";
        r.seq = seq++;
        r.counts = e.counts;
        r.counts_per_rev = e.counts_per_rev;
        r.angle_deg = static_cast<double>(e.counts) * 360.0 / e.counts_per_rev;
        rows.push_back(r);
    }
    seq = 0;
    for (const AirSample& a : s.air) {
        st::ChamberStateRow r = RunRow<st::ChamberStateRow>(run_id, a.utime);
        r.seq = seq++;
        r.cmd_id = -1;
        r.setpoint_c = kNan;
        r.air_c = a.air_c;
        rows.push_back(r);
    }
    for (const PowerRecord& p : s.power)
        for (int k = 0; k < units; ++k) {
            st::PowerStateRow r = RunRow<st::PowerStateRow>(run_id, p.utime);
            r.sensor_id = unit(k);
            r.power_on_utime = p.power_on_utime;
            r.source = p.source;
            rows.push_back(r);
        }
    for (const PlateauInput& p : s.run.plateaus) {
        st::PlateauRow r = RunRow<st::PlateauRow>(run_id, p.end_utime);
        r.plateau_id = p.plateau_id;
        r.start_utime = p.start_utime;
        r.end_utime = p.end_utime;
        r.n_samples = static_cast<int32_t>(p.n_samples);
        r.temp_mean_c = p.temp_mean_c;
        r.temp_sem_c = p.temp_sem_c;
        r.gyro_mean_v = p.gyro_mean_v;
        r.gyro_sem_v = p.gyro_sem_v;
        rows.push_back(r);
    }
    for (const SensitivityInput& si : s.run.sensitivities) {
        st::SensitivityRow r = RunRow<st::SensitivityRow>(run_id, si.utime);
        r.rotation_id = si.rotation_id;
        r.direction = si.direction;
        r.temp_c = si.temp_c;
        r.sensitivity_v_per_dps = si.sensitivity_v_per_dps;
        r.sensitivity_stderr_v_per_dps = si.stderr_v_per_dps;
        r.accepted = true;
        rows.push_back(r);
    }
    w.Write(rows, {});
}

void RemoveRunDb(const std::string& path) {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}

}  // namespace gyrocal::analysis::testing
