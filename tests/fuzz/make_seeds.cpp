// Writes the binary and generated seeds of the fuzz corpora (tests/fuzz/corpus/<harness>/):
// valid encodings of every message type, a message stream for the recorder's mapper, small
// gyrocal databases (current schema, schema v1) and a foreign SQLite file, and coefficient JSON
// as `gyrocal export --format json` writes it. The CSV and line-stream seeds are plain text,
// written by hand. Usage: fuzz_make_seeds tests/fuzz/corpus
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "gyrocal/analysis_t.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/json.hpp"
#include "store/db/schema.hpp"
#include "store/db/writer.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace {

namespace fs = std::filesystem;
using namespace gyrocal;
using namespace gyrocal::testing;

fs::path g_root;

void Put(const std::string& harness, const std::string& name, const std::vector<uint8_t>& bytes) {
    const fs::path dir = g_root / harness;
    fs::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
}

void PutText(const std::string& harness, const std::string& name, const std::string& text) {
    Put(harness, name, std::vector<uint8_t>(text.begin(), text.end()));
}

// The fitter's closed-loop analysis of one unit (ANALYSIS_<id>), as roundtrip_test.cpp's.
analysis_t ClosedLoopAnalysis() {
    analysis_t a{};
    a.utime = 1234, a.sensor_id = "S01", a.run_id = "R1", a.coeff_set_id = 1234;
    a.source = "closed-loop", a.is_final = true, a.outcome = "explained";
    a.headline = "missing effect: supply, explained";
    a.offset_rms_v_before = 1e-3, a.offset_rms_v_after = 1e-4, a.rate_rms_dps_before = 0.2;
    a.rate_rms_dps_after = 0.02, a.drift_dph_before = 80, a.drift_dph_after = 8;
    a.floor_rate_rms_dps = 0.01, a.floor_drift_dph = 5, a.candidates_json = "[]";
    a.added_json = "[]", a.result_json = "{\"residual_bins\": {}}";
    return a;
}

template <class Msg>
void PutMsg(const std::string& name, const Msg& m) {
    Put("decode_" + std::string(Msg::getTypeName()), name, EncodeMsg(m));
}

void MessageSeeds() {
    PutMsg("typical", Noise("S01"));
    PutMsg("typical", FitReport("S01"));
    PutMsg("typical", Gyro("S01", 7));
    PutMsg("typical", Encoder(3));
    PutMsg("typical", Chamber(2));
    PutMsg("typical", ChamberCmd("R1"));
    PutMsg("typical", TurntableCmd("R1"));
    PutMsg("typical", PlateauState("S01"));
    PutMsg("typical", Plateau("S01", "R1", 10, 20));
    PutMsg("typical", Sensitivity("S01", "R1", 30, 40));
    PutMsg("typical", Rate("S01", 5));
    PutMsg("typical", Status("gyrocal-recorder"));
    PutMsg("typical", Power("S01"));
    PutMsg("start", RunEvent("R1", "start", {"S01", "S02"}));
    PutMsg("stop", RunEvent("R1", "stop", {}));
    PutMsg("typical", Coeffs("S01", "R1", 99, {10, 11, 12}, {30}));
    PutMsg("empty_arrays", Coeffs("S01", "R1", 99, {}, {}));
    PutMsg("typical", GyroBatch("S01", 0, 16));
    PutMsg("empty", GyroBatch("S01", 0, 0));
    PutMsg("typical", EncoderBatch(0, 16));
    PutMsg("typical", RateBatch("S01", 0, 16));
    PutMsg("typical", FlowMark(1));
    PutMsg("typical", FlowAck(1));
    PutMsg("typical", ClosedLoopAnalysis());
}

// Records of [channel index][length, 2 bytes big-endian][payload] (recorder_map_fuzz.cpp).
void MapperSeed() {
    std::vector<uint8_t> out;
    auto add = [&](uint8_t channel, const std::vector<uint8_t>& b) {
        out.push_back(channel);
        out.push_back(static_cast<uint8_t>(b.size() >> 8));
        out.push_back(static_cast<uint8_t>(b.size() & 0xff));
        out.insert(out.end(), b.begin(), b.end());
    };
    add(3, EncodeMsg(RunEvent("R1", "start", {"S01"})));
    for (int64_t s = 0; s < 3; ++s) add(0, EncodeMsg(Gyro("S01", s == 2 ? 5 : s)));
    add(1, EncodeMsg(Encoder(0)));
    add(4, EncodeMsg(Coeffs("S01", "R1", 99, {10}, {30})));
    add(5, EncodeMsg(Status("gyrocal-plateau")));
    add(9, EncodeMsg(Power("S01")));
    add(10, EncodeMsg(Noise("S01")));
    add(11, EncodeMsg(FitReport("S01")));
    add(8, {1, 2, 3, 4, 5, 6, 7, 8, 9});
    add(0, EncodeMsg(GyroBatch("S01", 6, 4)));
    add(1, EncodeMsg(EncoderBatch(1, 3)));
    add(7, EncodeMsg(RateBatch("S01", 0, 2)));
    add(8, EncodeMsg(FlowMark(1)));
    add(3, EncodeMsg(RunEvent("R1", "stop", {})));
    Put("recorder_map", "run", out);
}

std::vector<uint8_t> ReadFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// A small database: 512-byte pages, a run with samples, a coefficient set, losses.
void DbSeeds() {
    const fs::path tmp = fs::temp_directory_path() / "gyrocal_make_seeds.db";
    for (const char* ext : {"", "-wal", "-shm"}) fs::remove(tmp.string() + ext);
    {
        db::StoreWriter w(tmp.string(), db::WriterInfo{"seed", "seedhost", 1});
        std::vector<db::Row> rows;
        db::RunEventRow e;
        e.run_id = "R1";
        e.event = "start";
        e.sensor_ids = {"S01"};
        e.config_json = "{}";
        rows.push_back(e);
        for (int64_t s = 0; s < 5; ++s) {
            db::GyroRow g;
            g.run_id = "R1";
            g.sensor_id = "S01";
            g.utime = kT0Utime + s * kPeriodUs;
            g.seq = s;
            g.gyro_v = 2.5;
            rows.push_back(g);
        }
        w.Write(rows, {{{"R1", "GYRO_S01"}, db::LossDelta{2, 0, 0, 1}}});
        w.db().Exec("PRAGMA wal_checkpoint(TRUNCATE)");
        w.db().Exec("PRAGMA journal_mode = DELETE");
        w.db().Exec("PRAGMA page_size = 512");
        w.db().Exec("VACUUM");
    }
    Put("store_open", "gyrocal_v" + std::to_string(db::kSchemaVersion), ReadFile(tmp));
    for (const char* ext : {"", "-wal", "-shm"}) fs::remove(tmp.string() + ext);
    {
        db::Db db(tmp.string(), db::Db::Mode::kReadWriteCreate);
        db.Exec("PRAGMA page_size = 512");
        db::Migrate(db, 1);
        db.Exec("VACUUM");
    }
    Put("store_open", "gyrocal_v1", ReadFile(tmp));
    for (const char* ext : {"", "-wal", "-shm"}) fs::remove(tmp.string() + ext);
    {
        db::Db db(tmp.string(), db::Db::Mode::kReadWriteCreate);
        db.Exec("PRAGMA page_size = 512; CREATE TABLE t(a, b); INSERT INTO t VALUES (1, 'x')");
    }
    Put("store_open", "foreign_sqlite", ReadFile(tmp));
    fs::remove(tmp);
}

void JsonSeeds() {
    const model::CoeffSet set = model::FromMsg(Coeffs("S01", "R1", 99, {10}, {30}));
    nlohmann::json exported;
    exported["coeff_sets"] = nlohmann::json::array({model::ToJson(set)});
    PutText("coeff_json", "export", exported.dump(1));
    PutText("coeff_json", "one_set", model::ToJson(set).dump());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: fuzz_make_seeds CORPUS_DIR (tests/fuzz/corpus)\n";
        return 2;
    }
    g_root = argv[1];
    MessageSeeds();
    MapperSeed();
    DbSeeds();
    JsonSeeds();
    return 0;
}
