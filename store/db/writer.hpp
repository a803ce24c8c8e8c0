#pragma once
// StoreWriter: the only code that writes the database. Synchronous, one connection, prepared
// statements; Write() stores a batch of rows and loss deltas in ONE transaction, so after a
// crash the database holds whole batches only.
//
// Runs: a RunEventRow "start" creates/updates runs(run_id) with version, configuration, command
// line and host; "stop"/"abort" set stopped_utime, outcome and reason. Any other row whose run_id
// is not yet in runs creates a bare runs row, so no row ever points at a missing run.
//
// gyro_samples has no per-row index (it would cost two thirds of the insert rate); instead each
// batch adds one gyro_blocks row per (run, sensor) with the rowid and utime ranges it wrote.
//
// Coefficient sets are kept once per (run_id, sensor_id, coeff_set_id, source): a repeat (the
// fitter's re-publish of an unchanged set on stop, or a set `gyrocal analyze` stored directly
// and then published) is not stored twice (see analyses.hpp). Plateaus and sensitivity points
// likewise, once per (run_id, sensor_id, plateau_id / rotation_id): `gyrocal calibrate`
// publishes a run's stored ones again to rebuild a restarted fitter.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

struct WriterInfo {
    std::string recorder_version;  // stored with each run the recorder sees start
    std::string host;
    int32_t pid = 0;
};

using LossKey = std::pair<std::string, std::string>;  // (run_id, channel)
using LossMap = std::map<LossKey, LossDelta>;

class StoreWriter {
public:
    // Opens (creating when missing) and migrates `path`. Throws StoreError naming the file.
    StoreWriter(const std::string& path, WriterInfo info);
    ~StoreWriter();

    // The newest run that has a start but no stop/abort ("" when none): where a restarted
    // recorder continues.
    std::string OpenRunId();
    // The last stored seq of each sample stream of `run_id` (gyro per sensor, encoder, chamber
    // state), so that a restarted recorder counts what it missed while down as seq gaps.
    struct StreamSeq {
        enum class Kind { kGyro, kEncoder, kChamberState } kind;
        std::string sensor_id;  // kGyro only
        int64_t seq = 0;
    };
    std::vector<StreamSeq> LastSeqs(const std::string& run_id);
    // Records this recorder session (wall clock [us]); EndSession marks a clean stop.
    void BeginSession(int64_t wall_utime, const std::string& resumed_run_id);
    void EndSession(int64_t wall_utime);

    // Writes all rows and adds all loss deltas in one transaction; throws StoreError (the
    // transaction is rolled back) on failure. The call after a failure first opens the database
    // again (so a failure to reopen is thrown from there): the same rows can simply be written
    // again once the storage recovers (see IsStorageFault).
    void Write(const std::vector<Row>& rows, const LossMap& losses);

    // Throws StoreError when the last reopen failed.
    Db& db();

private:
    void Open();
    void WriteBatch(const std::vector<Row>& rows, const LossMap& losses);
    struct Statements;
    void EnsureRun(const std::string& run_id, int64_t recv_utime);
    void EnsureSensor(const std::string& sensor_id, int64_t recv_utime);
    void WriteOne(const Row& row);
    void NoteBlock(const GyroRow& g, int64_t rowid);
    void WriteRunEvent(const RunEventRow& r);
    void WriteCoeffSet(const CoeffSetRow& r);
    void WriteNoise(const NoiseRow& r);            // writer_fit.cpp
    void WriteFitReport(const FitReportRow& r);    // writer_fit.cpp
    void WriteClosedLoop(const ClosedLoopRow& r);  // writer_fit.cpp

    std::string path_;
    WriterInfo info_;
    bool reopen_ = false;  // the last Write failed
    std::unique_ptr<Db> db_;
    std::unique_ptr<Statements> st_;
    // gyro_blocks of the batch being written, per (run_id, sensor_id).
    struct Block {
        int64_t first_rowid = 0, last_rowid = 0, min_utime = 0, max_utime = 0, n_samples = 0;
    };
    std::map<std::pair<std::string, std::string>, Block> blocks_;
    std::unordered_set<std::string> known_runs_;
    std::unordered_set<std::string> known_sensors_;
    int64_t session_id_ = -1;
};

}  // namespace gyrocal::db
