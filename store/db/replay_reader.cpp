#include "replay_reader.hpp"

#include "query.hpp"

namespace gyrocal::store {

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
                g.recv_utime = s.Int(0);
                g.run_id = s.Text(1);
                g.sensor_id = s.Text(2);
                g.utime = s.Int(3);
                g.seq = s.Int(4);
                g.gyro_v = s.Real(5);
                g.temp_v = s.Real(6);
                g.temp_c = s.Real(7);
                g.supply_v = s.Real(8);
                g.has_adc = s.Int(9) != 0;
                g.gyro_counts = static_cast<int32_t>(s.Int(10));
                g.temp_counts = static_cast<int32_t>(s.Int(11));
                g.supply_counts = s.IsNull(12) ? -1 : static_cast<int32_t>(s.Int(12));
                return g;
            }
            case 1: {
                EncoderRow e;
                e.recv_utime = s.Int(0);
                e.run_id = s.Text(1);
                e.encoder_id = s.Text(2);
                e.utime = s.Int(3);
                e.seq = s.Int(4);
                e.counts = s.Int(5);
                e.counts_per_rev = static_cast<int32_t>(s.Int(6));
                e.angle_deg = s.Real(7);
                return e;
            }
            case 2: {
                ChamberStateRow c;
                c.recv_utime = s.Int(0);
                c.run_id = s.Text(1);
                c.utime = s.Int(2);
                c.seq = s.Int(3);
                c.cmd_id = s.Int(4);
                c.setpoint_c = s.Real(5);
                c.air_c = s.Real(6);
                c.at_setpoint = s.Int(7) != 0;
                c.fault = s.Text(8);
                return c;
            }
            case 4: {
                PowerStateRow p;
                p.recv_utime = s.Int(0);
                p.run_id = s.Text(1);
                p.sensor_id = s.Text(2);
                p.utime = s.Int(3);
                p.seq = s.Int(4);
                p.power_on_utime = s.Int(5);
                p.source = s.Text(6);
                return p;
            }
            default: {
                RunEventRow e;
                e.recv_utime = s.Int(0);
                e.run_id = s.Text(1);
                e.utime = s.Int(2);
                e.event = s.Text(3);
                e.reason = s.Text(4);
                e.setpoint_index = static_cast<int32_t>(s.Int(5));
                e.setpoint_c = s.Real(6);
                e.sensor_ids = ParseIds(s.Text(7));
                e.software_version = s.Text(8);
                e.config_json = s.Text(9);
                e.command_line = s.Text(10);
                e.host = s.Text(11);
                return e;
            }
        }
    }
};

ReplayReader::ReplayReader(Db& db, const std::string& run_id) {
    if (!RunExists(db, run_id)) {
        throw NotFound("no run '" + run_id + "' in database '" + db.path() + "'");
    }
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        "SELECT recv_utime, run_id, sensor_id, utime, seq, gyro_v, temp_v, temp_c, supply_v, "
        "has_adc, gyro_counts, temp_counts, supply_counts FROM gyro_samples WHERE run_id = ?1 "
        "AND rowid BETWEEN (SELECT min(first_rowid) FROM gyro_blocks WHERE run_id = ?1) "
        "AND (SELECT max(last_rowid) FROM gyro_blocks WHERE run_id = ?1) ORDER BY rowid",
        run_id, 0));
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
    cursors_.push_back(std::make_unique<Cursor>(
        db,
        "SELECT recv_utime, run_id, utime, event, reason, setpoint_index, setpoint_c, "
        "sensor_ids_json, software_version, config_json, command_line, host FROM run_events "
        "WHERE run_id = ? ORDER BY rowid",
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

}  // namespace gyrocal::store
