#include "store/db/writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <type_traits>
#include <variant>

#include "store/db/analyses.hpp"
#include "store/db/central_url.hpp"
#include "store/db/schema.hpp"

namespace gyrocal::db {

namespace {

// Why this process cannot write the database at `path`: its file, its WAL, or the folder where
// SQLite creates the WAL and shared-memory files refuse writes (EROFS: read-only file system,
// EPERM: an immutable file, EACCES: permissions; access(2) says so also for root). {0, ""}
// when nothing refuses. SQLite itself reports such a failure as a plain "disk I/O error" or
// "unable to open database file", without the cause.
std::pair<int, std::string> NotWritable(const std::string& path) {
    const std::string dir = std::filesystem::path(path).parent_path().string();
    for (const std::string& p : {path, path + "-wal", dir.empty() ? std::string(".") : dir}) {
        if (::access(p.c_str(), W_OK) != 0 && errno != ENOENT) {
            const int e = errno;
            return {e, "cannot write '" + p + "': " + std::strerror(e)};
        }
    }
    return {0, ""};
}

// `e` with the reason the storage refuses writes added, when there is one.
StoreError WithCause(const StoreError& e, const std::string& path) {
    if (!IsStorageFault(e.sqlite_code())) return e;
    const auto [os, why] = NotWritable(path);
    if (os == 0) return e;
    return StoreError(std::string(e.what()) + "; " + why, e.sqlite_code(), os);
}

}  // namespace

struct StoreWriter::Statements {
    explicit Statements(Db& db)
        : gyro(db,
               "INSERT INTO gyro_samples(run_id, sensor_id, utime, seq, gyro_v, temp_v, "
               "temp_c, supply_v, has_adc, gyro_counts, temp_counts, supply_counts, "
               "recv_utime) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)"),
          encoder(db,
                  "INSERT INTO encoder_samples(run_id, encoder_id, utime, seq, counts, "
                  "counts_per_rev, angle_deg, recv_utime) VALUES (?,?,?,?,?,?,?,?)"),
          chamber(db,
                  "INSERT INTO chamber_states(run_id, utime, seq, cmd_id, setpoint_c, air_c, "
                  "at_setpoint, fault, recv_utime) VALUES (?,?,?,?,?,?,?,?,?)"),
          chamber_cmd(db,
                      "INSERT INTO chamber_cmds(run_id, msg_run_id, utime, cmd_id, "
                      "setpoint_c, ramp_rate_c_per_min, recv_utime) VALUES (?,?,?,?,?,?,?)"),
          turntable_cmd(db,
                        "INSERT INTO turntable_cmds(run_id, msg_run_id, utime, cmd_id, "
                        "move_deg, rate_dps, accel_dps2, recv_utime) "
                        "VALUES (?,?,?,?,?,?,?,?)"),
          plateau_state(db,
                        "INSERT INTO plateau_states(run_id, sensor_id, utime, state, temp_c, "
                        "temp_slope_c_per_min, temp_std_c, stable_for_s, "
                        "averaging_progress, last_plateau_id, recv_utime) "
                        "VALUES (?,?,?,?,?,?,?,?,?,?,?)"),
          plateau(db,
                  "INSERT INTO plateaus(run_id, sensor_id, plateau_id, utime, setpoint_c, "
                  "start_utime, end_utime, first_seq, last_seq, n_samples, "
                  "n_excluded_motion, seq_gaps, temp_mean_c, temp_std_c, temp_sem_c, "
                  "temp_slope_c_per_min, gyro_mean_v, gyro_std_v, gyro_sem_v, temp_mean_v, "
                  "supply_mean_v, recv_utime) "
                  "SELECT ?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16,?17,?18,?19,"
                  "?20,?21,?22 "
                  "WHERE NOT EXISTS (SELECT 1 FROM plateaus WHERE run_id = ?1 AND "
                  "sensor_id = ?2 AND plateau_id = ?3)"),
          sensitivity(db,
                      "INSERT INTO sensitivity_points(run_id, sensor_id, rotation_id, utime, "
                      "start_utime, end_utime, first_seq, last_seq, n_samples, direction, "
                      "temp_c, encoder_angle_deg, offset_v, offset_stderr_v, integral_v_s, "
                      "sensitivity_v_per_dps, sensitivity_stderr_v_per_dps, accepted, "
                      "reject_reason, recv_utime) "
                      "SELECT ?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16,?17,?18,"
                      "?19,?20 "
                      "WHERE NOT EXISTS (SELECT 1 FROM sensitivity_points WHERE run_id = ?1 "
                      "AND sensor_id = ?2 AND rotation_id = ?3)"),
          rate(db,
               "INSERT INTO rates(run_id, sensor_id, utime, seq, rate_dps, angle_deg, temp_c, "
               "coeff_set_id, range_flag, recv_utime) VALUES (?,?,?,?,?,?,?,?,?,?)"),
          status(db,
                 "INSERT INTO status(run_id, utime, process, host, pid, state, received, "
                 "published, decode_errors, seq_gaps, queue_drops, rejected, last_reject, "
                 "extra_json, recv_utime) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
          run_event(db,
                    "INSERT INTO run_events(run_id, utime, event, reason, setpoint_index, "
                    "setpoint_c, sensor_ids_json, software_version, config_json, "
                    "command_line, host, recv_utime) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)"),
          run_start(db,
                    "INSERT INTO runs(run_id, started_utime, outcome, software_version, "
                    "config_json, command_line, host, recorder_version, recorder_host, "
                    "first_recv_utime) VALUES (?1,?2,'running',?3,?4,?5,?6,?7,?8,?9) "
                    "ON CONFLICT(run_id) DO UPDATE SET started_utime = ?2, "
                    "software_version = ?3, config_json = ?4, command_line = ?5, host = ?6, "
                    "recorder_version = ?7, recorder_host = ?8"),
          run_stop(db,
                   "INSERT INTO runs(run_id, stopped_utime, outcome, reason, first_recv_utime) "
                   "VALUES (?1,?2,?3,?4,?5) ON CONFLICT(run_id) DO UPDATE SET "
                   "stopped_utime = ?2, outcome = ?3, reason = ?4"),
          block(db,
                "INSERT INTO gyro_blocks(run_id, sensor_id, first_rowid, last_rowid, "
                "min_utime, max_utime, n_samples) VALUES (?,?,?,?,?,?,?)"),
          run_bare(db, "INSERT OR IGNORE INTO runs(run_id, first_recv_utime) VALUES (?,?)"),
          power(db,
                "INSERT INTO power_states(run_id, sensor_id, utime, seq, power_on_utime, "
                "source, recv_utime) VALUES (?,?,?,?,?,?,?)"),
          run_sensor(db, "INSERT OR IGNORE INTO run_sensors(run_id, sensor_id) VALUES (?,?)"),
          sensor(db, "INSERT OR IGNORE INTO sensors(sensor_id, first_recv_utime) VALUES (?,?)"),
          raw(db,
              "INSERT INTO raw_events(run_id, channel, recv_utime, fingerprint, reason, data) "
              "VALUES (?,?,?,?,?,?)"),
          loss(db,
               "INSERT INTO losses(run_id, channel, seq_gaps, seq_backwards, decode_errors, "
               "queue_drops) VALUES (?1,?2,?3,?4,?5,?6) ON CONFLICT(run_id, channel) DO "
               "UPDATE SET seq_gaps = seq_gaps + ?3, seq_backwards = seq_backwards + ?4, "
               "decode_errors = decode_errors + ?5, queue_drops = queue_drops + ?6") {}

    Stmt gyro, encoder, chamber, chamber_cmd, turntable_cmd, plateau_state, plateau, sensitivity,
        rate, status, run_event, run_start, run_stop, block, run_bare, power, run_sensor, sensor,
        raw, loss;
};

StoreWriter::StoreWriter(const std::string& path, WriterInfo info)
    : path_(path), info_(std::move(info)) {
    try {
        Open();
    } catch (const StoreError& e) {
        throw WithCause(e, path_);
    }
}

StoreWriter::~StoreWriter() = default;

void StoreWriter::Open() {
    st_.reset();
    db_.reset();
    known_runs_.clear();
    known_sensors_.clear();
    auto db = std::make_unique<Db>(path_, Db::Mode::kReadWriteCreate);
    ConfigureConnection(*db);
    Migrate(*db);
    // Shorter than the readers' 5 s, so that a writer holding the lock shows as "locked" on
    // STATUS within a second; the rows wait in the AsyncWriter meanwhile and are written again.
    db->SetBusyTimeout(1000);
    auto st = std::make_unique<Statements>(*db);
    Stmt runs(*db, "SELECT run_id FROM runs");
    while (runs.Step()) known_runs_.insert(runs.Text(0));
    Stmt sensors(*db, "SELECT sensor_id FROM sensors");
    while (sensors.Step()) known_sensors_.insert(sensors.Text(0));
    db_ = std::move(db);
    st_ = std::move(st);
}

Db& StoreWriter::db() {
    if (!db_) throw StoreError("database '" + path_ + "' is not open (the last reopen failed)");
    return *db_;
}

std::string StoreWriter::OpenRunId() {
    Stmt s(db(),
           "SELECT run_id FROM runs WHERE run_id != '' AND started_utime IS NOT NULL AND "
           "stopped_utime IS NULL AND outcome = 'running' "
           "ORDER BY first_recv_utime DESC, rowid DESC LIMIT 1");
    return s.Step() ? s.Text(0) : std::string();
}

std::vector<StoreWriter::StreamSeq> StoreWriter::LastSeqs(const std::string& run_id) {
    std::vector<StreamSeq> out;
    Db& d = db();
    // One index seek per sensor (run_id, sensor_id, utime), not a scan of the run.
    Stmt sensors(d, "SELECT sensor_id FROM sensors");
    Stmt last(d,
              "SELECT g.seq FROM (SELECT first_rowid, last_rowid FROM gyro_blocks WHERE "
              "run_id = ?1 AND sensor_id = ?2 ORDER BY max_utime DESC LIMIT 1) b JOIN gyro_samples "
              "g ON g.rowid BETWEEN b.first_rowid AND b.last_rowid AND g.run_id = ?1 AND "
              "g.sensor_id = ?2 ORDER BY g.utime DESC, g.rowid DESC LIMIT 1");
    while (sensors.Step()) {
        const std::string id = sensors.Text(0);
        last.Bind(1, run_id).Bind(2, id);
        if (last.Step()) out.push_back({StreamSeq::Kind::kGyro, id, last.Int(0)});
        last.Reset();
    }
    Stmt enc(d, "SELECT seq FROM encoder_samples WHERE run_id = ? ORDER BY utime DESC LIMIT 1");
    enc.Bind(1, run_id);
    if (enc.Step()) out.push_back({StreamSeq::Kind::kEncoder, "", enc.Int(0)});
    Stmt ch(d, "SELECT seq FROM chamber_states WHERE run_id = ? ORDER BY utime DESC LIMIT 1");
    ch.Bind(1, run_id);
    if (ch.Step()) out.push_back({StreamSeq::Kind::kChamberState, "", ch.Int(0)});
    return out;
}

void StoreWriter::BeginSession(int64_t wall_utime, const std::string& resumed_run_id) {
    Stmt s(db(),
           "INSERT INTO recorder_sessions(started_wall_utime, host, pid, recorder_version, "
           "resumed_run_id) VALUES (?,?,?,?,?)");
    s.Bind(1, wall_utime).Bind(2, info_.host).Bind(3, info_.pid).Bind(4, info_.recorder_version);
    s.Bind(5, resumed_run_id).Run();
    session_id_ = db_->LastInsertRowId();
}

void StoreWriter::EndSession(int64_t wall_utime) {
    if (session_id_ < 0) return;
    Stmt s(db(), "UPDATE recorder_sessions SET stopped_wall_utime = ? WHERE session_id = ?");
    s.Bind(1, wall_utime).Bind(2, session_id_).Run();
}

void StoreWriter::EnsureRun(const std::string& run_id, int64_t recv_utime) {
    if (known_runs_.count(run_id)) return;
    st_->run_bare.Bind(1, run_id).Bind(2, recv_utime).Run();
    known_runs_.insert(run_id);
}

void StoreWriter::EnsureSensor(const std::string& sensor_id, int64_t recv_utime) {
    if (known_sensors_.count(sensor_id)) return;
    st_->sensor.Bind(1, sensor_id).Bind(2, recv_utime).Run();
    known_sensors_.insert(sensor_id);
}

void StoreWriter::Write(const std::vector<Row>& rows, const LossMap& losses) {
    try {
        WriteBatch(rows, losses);
    } catch (const StoreError& e) {
        throw WithCause(e, path_);
    }
}

void StoreWriter::WriteBatch(const std::vector<Row>& rows, const LossMap& losses) {
    // After a failed write the connection is opened again: a file that was replaced, removed or
    // remounted is then the one at the path, and the caches of known runs and sensors, which the
    // rolled-back transaction may have filled, are read again from what was committed.
    if (reopen_) Open();
    reopen_ = true;
    if (db_->HasMoved()) {  // SQLite would go on writing into the removed file, silently
        throw StoreError("database '" + path_ +
                             "': the file was removed or replaced while open; "
                             "it is opened (created) again at that path",
                         SQLITE_READONLY_DBMOVED);
    }
    {
        Transaction tx(*db_);
        blocks_.clear();
        for (const Row& row : rows) WriteOne(row);
        for (const auto& [key, b] : blocks_) {
            Stmt& s = st_->block;
            s.Bind(1, key.first).Bind(2, key.second).Bind(3, b.first_rowid).Bind(4, b.last_rowid);
            s.Bind(5, b.min_utime).Bind(6, b.max_utime).Bind(7, b.n_samples).Run();
        }
        for (const auto& [key, d] : losses) {
            if (d.Empty()) continue;
            EnsureRun(key.first, 0);
            st_->loss.Bind(1, key.first).Bind(2, key.second).Bind(3, d.seq_gaps);
            st_->loss.Bind(4, d.seq_backwards).Bind(5, d.decode_errors).Bind(6, d.queue_drops);
            st_->loss.Run();
        }
        tx.Commit();
    }
    reopen_ = false;
}

namespace {

// std::visit over one lambda per row type.
template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};
// Needed by clang 14 (the sanitizer builds), which does not deduce an aggregate's arguments.
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

// The rows that register their sensor (table sensors) before they are written: a unit's samples,
// points, coefficient sets and reports (rates, power and plateau states do not).
template <class R>
constexpr bool kRegistersSensor =
    std::is_same_v<R, GyroRow> || std::is_same_v<R, PlateauRow> ||
    std::is_same_v<R, SensitivityRow> || std::is_same_v<R, CoeffSetRow> ||
    std::is_same_v<R, NoiseRow> || std::is_same_v<R, FitReportRow> ||
    std::is_same_v<R, ClosedLoopRow>;

// One INSERT per row type, bound in the column order of the statements prepared above.
void Insert(Stmt& s, const EncoderRow& e) {
    s.BindAll(e.run_id, e.encoder_id, e.utime, e.seq, e.counts, e.counts_per_rev, e.angle_deg,
              e.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const ChamberStateRow& c) {
    s.BindAll(c.run_id, c.utime, c.seq, c.cmd_id, c.setpoint_c, c.air_c, c.at_setpoint ? 1 : 0,
              c.fault, c.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const PowerStateRow& pw) {
    s.BindAll(pw.run_id, pw.sensor_id, pw.utime, pw.seq, pw.power_on_utime, pw.source,
              pw.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const ChamberCmdRow& cc) {
    s.BindAll(cc.run_id, cc.msg_run_id, cc.utime, cc.cmd_id, cc.setpoint_c, cc.ramp_rate_c_per_min,
              cc.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const TurntableCmdRow& t) {
    s.BindAll(t.run_id, t.msg_run_id, t.utime, t.cmd_id, t.move_deg, t.rate_dps, t.accel_dps2,
              t.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const PlateauStateRow& ps) {
    s.BindAll(ps.run_id, ps.sensor_id, ps.utime, ps.state, ps.temp_c, ps.temp_slope_c_per_min,
              ps.temp_std_c, ps.stable_for_s, ps.averaging_progress, ps.last_plateau_id,
              ps.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const RateRow& r) {
    s.BindAll(r.run_id, r.sensor_id, r.utime, r.seq, r.rate_dps, r.angle_deg, r.temp_c,
              r.coeff_set_id, r.range_flag, r.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const StatusRow& st) {
    s.BindAll(st.run_id, st.utime, st.process, st.host, st.pid, st.state, st.received, st.published,
              st.decode_errors, st.seq_gaps, st.queue_drops, st.rejected, st.last_reject,
              st.extra_json, st.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const RawEventRow& raw) {
    s.Bind(1, raw.run_id).Bind(2, raw.channel).Bind(3, raw.recv_utime);
    s.Bind(4, raw.fingerprint_hex).Bind(5, raw.reason);
    s.BindBlob(6, raw.data.data(), static_cast<int>(raw.data.size())).Run();
}

void Insert(Stmt& s, const GyroRow& g) {
    s.Bind(1, g.run_id).Bind(2, g.sensor_id).Bind(3, g.utime).Bind(4, g.seq);
    s.Bind(5, g.gyro_v).Bind(6, g.temp_v).Bind(7, g.temp_c).Bind(8, g.supply_v);
    s.Bind(9, g.has_adc ? 1 : 0);
    if (g.has_adc) {
        s.Bind(10, g.gyro_counts).Bind(11, g.temp_counts);
    }
    if (g.supply_counts >= 0) s.Bind(12, g.supply_counts);  // -1 = not measured -> NULL
    s.Bind(13, g.recv_utime).Run();
}

void Insert(Stmt& s, const PlateauRow& p) {
    s.BindAll(p.run_id, p.sensor_id, p.plateau_id, p.utime, p.setpoint_c, p.start_utime,
              p.end_utime, p.first_seq, p.last_seq, p.n_samples, p.n_excluded_motion, p.seq_gaps,
              p.temp_mean_c, p.temp_std_c, p.temp_sem_c, p.temp_slope_c_per_min, p.gyro_mean_v,
              p.gyro_std_v, p.gyro_sem_v, p.temp_mean_v, p.supply_mean_v, p.recv_utime);
    s.Run();
}

void Insert(Stmt& s, const SensitivityRow& sp) {
    s.BindAll(sp.run_id, sp.sensor_id, sp.rotation_id, sp.utime, sp.start_utime, sp.end_utime,
              sp.first_seq, sp.last_seq, sp.n_samples, sp.direction, sp.temp_c,
              sp.encoder_angle_deg, sp.offset_v, sp.offset_stderr_v, sp.integral_v_s,
              sp.sensitivity_v_per_dps, sp.sensitivity_stderr_v_per_dps, sp.accepted ? 1 : 0,
              sp.reject_reason, sp.recv_utime);
    s.Run();
}

}  // namespace

void StoreWriter::WriteOne(const Row& row) {
    std::visit(
        [this](const auto& r) {
            EnsureRun(r.run_id, r.recv_utime);
            if constexpr (kRegistersSensor<std::decay_t<decltype(r)>>) {
                EnsureSensor(r.sensor_id, r.recv_utime);
            }
        },
        row);
    const Overloaded write{
        [this](const GyroRow& g) {
            Insert(st_->gyro, g);
            NoteBlock(g, db_->LastInsertRowId());
        },
        [this](const CoeffSetRow& cs) { WriteCoeffSet(cs); },
        [this](const RunEventRow& ev) { WriteRunEvent(ev); },
        [this](const NoiseRow& n) { WriteNoise(n); },
        [this](const FitReportRow& f) { WriteFitReport(f); },
        [this](const ClosedLoopRow& a) { WriteClosedLoop(a); },
        [this](const PlateauRow& p) { Insert(st_->plateau, p); },
        [this](const SensitivityRow& sp) { Insert(st_->sensitivity, sp); },
        [this](const EncoderRow& e) { Insert(st_->encoder, e); },
        [this](const ChamberStateRow& c) { Insert(st_->chamber, c); },
        [this](const PowerStateRow& pw) { Insert(st_->power, pw); },
        [this](const ChamberCmdRow& cc) { Insert(st_->chamber_cmd, cc); },
        [this](const TurntableCmdRow& t) { Insert(st_->turntable_cmd, t); },
        [this](const PlateauStateRow& ps) { Insert(st_->plateau_state, ps); },
        [this](const RateRow& r) { Insert(st_->rate, r); },
        [this](const StatusRow& st) { Insert(st_->status, st); },
        [this](const RawEventRow& raw) { Insert(st_->raw, raw); },
    };
    std::visit(write, row);
}

void StoreWriter::NoteBlock(const GyroRow& g, int64_t rowid) {
    auto [it, fresh] = blocks_.try_emplace({g.run_id, g.sensor_id});
    Block& b = it->second;
    if (fresh) {
        b.first_rowid = rowid;
        b.min_utime = b.max_utime = g.utime;
    }
    b.last_rowid = rowid;
    b.min_utime = std::min(b.min_utime, g.utime);
    b.max_utime = std::max(b.max_utime, g.utime);
    ++b.n_samples;
}

void StoreWriter::WriteRunEvent(const RunEventRow& r) {
    // A central database URL in a run's configuration or command line (e.g. a recorder told to
    // push) is stored without its password.
    const std::string config = WithoutCredentialsIn(r.config_json);
    const std::string command = WithoutCredentialsIn(r.command_line);
    Stmt& s = st_->run_event;
    s.Bind(1, r.run_id).Bind(2, r.utime).Bind(3, r.event).Bind(4, r.reason);
    s.Bind(5, r.setpoint_index).Bind(6, r.setpoint_c);
    s.Bind(7, nlohmann::json(r.sensor_ids).dump()).Bind(8, r.software_version);
    s.Bind(9, config).Bind(10, command).Bind(11, r.host).Bind(12, r.recv_utime);
    s.Run();
    if (r.event == "start") {
        Stmt& u = st_->run_start;
        u.Bind(1, r.run_id).Bind(2, r.utime).Bind(3, r.software_version).Bind(4, config);
        u.Bind(5, command).Bind(6, r.host).Bind(7, info_.recorder_version);
        u.Bind(8, info_.host).Bind(9, r.recv_utime).Run();
        for (const auto& id : r.sensor_ids) st_->run_sensor.Bind(1, r.run_id).Bind(2, id).Run();
    } else if (r.event == "stop" || r.event == "abort") {
        Stmt& u = st_->run_stop;
        u.Bind(1, r.run_id).Bind(2, r.utime).Bind(3, r.event).Bind(4, r.reason);
        u.Bind(5, r.recv_utime).Run();
    }
    known_runs_.insert(r.run_id);
}

void StoreWriter::WriteCoeffSet(const CoeffSetRow& r) {
    // Kept once per (run, sensor, coeff_set_id, source): a set that `gyrocal analyze` stored
    // directly and then published is not stored again when the recorder hears it.
    InsertCoeffSetOnce(*db_, r);
}

}  // namespace gyrocal::db
