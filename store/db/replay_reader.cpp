#include "store/db/replay_reader.hpp"

#include "store/db/query.hpp"

namespace gyrocal::db {

// One table's rows of a run in insertion (= reception) order.
struct ReplayReader::Cursor {
    Stmt stmt;
    int kind;
    bool has = false;
    int64_t recv_utime = 0;
    Cursor(Db& db, const std::string& sql, const std::string& run_id, int k)
        : stmt(db, sql), kind(k) {
        stmt.Bind(1, run_id);
        Advance();
    }
    void Advance() {
        has = stmt.Step();
        if (has) recv_utime = stmt.Int(0);
    }
    Row Read() const {
        const Stmt& s = stmt;
        switch (kind) {
            case 0: {
                GyroRow g;
                s.Read(0, g.recv_utime, g.run_id, g.sensor_id, g.utime, g.seq, g.gyro_v, g.temp_v,
                       g.temp_c, g.supply_v, g.has_adc, g.gyro_counts, g.temp_counts);
                g.supply_counts = s.IsNull(12) ? -1 : static_cast<int32_t>(s.Int(12));
                return g;
            }
            case 5: {  // GyroColumns::kAnalysis
                GyroRow g;
                s.Read(0, g.recv_utime, g.sensor_id, g.utime, g.seq, g.gyro_v, g.temp_c,
                       g.supply_v);
                return g;
            }
            case 1: {
                EncoderRow e;
                s.Read(0, e.recv_utime, e.run_id, e.encoder_id, e.utime, e.seq, e.counts,
                       e.counts_per_rev, e.angle_deg);
                return e;
            }
            case 2: {
                ChamberStateRow c;
                s.Read(0, c.recv_utime, c.run_id, c.utime, c.seq, c.cmd_id, c.setpoint_c, c.air_c,
                       c.at_setpoint, c.fault);
                return c;
            }
            case 4: {
                PowerStateRow p;
                s.Read(0, p.recv_utime, p.run_id, p.sensor_id, p.utime, p.seq, p.power_on_utime,
                       p.source);
                return p;
            }
            default: {
                RunEventRow e = ReadRunEvent(s, 1);
                e.recv_utime = s.Int(0);
                return e;
            }
        }
    }
};

ReplayReader::ReplayReader(Db& db, const std::string& run_id, GyroColumns gyro) {
    RequireRun(db, run_id);
    const bool all = gyro == GyroColumns::kAll;
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        std::string(all ? "SELECT recv_utime, run_id, sensor_id, utime, seq, gyro_v, temp_v, "
                          "temp_c, supply_v, has_adc, gyro_counts, temp_counts, supply_counts "
                        : "SELECT recv_utime, sensor_id, utime, seq, gyro_v, temp_c, supply_v ") +
            "FROM gyro_samples WHERE run_id = ?1 "
            "AND rowid BETWEEN (SELECT min(first_rowid) FROM gyro_blocks WHERE run_id = ?1) "
            "AND (SELECT max(last_rowid) FROM gyro_blocks WHERE run_id = ?1) ORDER BY rowid",
        run_id, all ? 0 : 5));
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        "SELECT recv_utime, run_id, encoder_id, utime, seq, counts, counts_per_rev, angle_deg "
        "FROM encoder_samples WHERE run_id = ? ORDER BY rowid",
        run_id, 1));
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        "SELECT recv_utime, run_id, utime, seq, cmd_id, setpoint_c, air_c, at_setpoint, fault "
        "FROM chamber_states WHERE run_id = ? ORDER BY rowid",
        run_id, 2));
    cursors_.push_back(
        std::make_unique<Cursor>(db,
                                 std::string("SELECT recv_utime, ") + kRunEventColumns +
                                     " FROM run_events WHERE run_id = ? ORDER BY rowid",
                                 run_id, 3));
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        "SELECT recv_utime, run_id, sensor_id, utime, seq, power_on_utime, source "
        "FROM power_states WHERE run_id = ? ORDER BY rowid",
        run_id, 4));
}

ReplayReader::~ReplayReader() = default;

std::optional<Row> ReplayReader::Next() {
    Cursor* best = nullptr;
    for (auto& c : cursors_) {
        // Ties: run events (kind 3) first so a start precedes the samples of the same instant.
        if (c->has && (best == nullptr || c->recv_utime < best->recv_utime ||
                       (c->recv_utime == best->recv_utime && c->kind == 3))) {
            best = c.get();
        }
    }
    if (best == nullptr) return std::nullopt;
    Row r = best->Read();
    best->Advance();
    return r;
}

}  // namespace gyrocal::db
