#pragma once
// Reads a stored run back in reception order, for gyrocal-replay.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

// Streams the replayable messages of a run (gyro, encoder, chamber state, run events, power) in
// reception order (merged by recv_utime). Throws NotFound.
class ReplayReader {
public:
    // kAll: every stored column (gyrocal-replay republishes them). kAnalysis: a gyro row carries
    // only recv_utime, sensor_id, utime, seq, gyro_v, temp_c and supply_v (the rest default): a
    // day of 16 units is 137M rows, and stepping out the other six columns was half the read.
    enum class GyroColumns { kAll, kAnalysis };
    ReplayReader(Db& db, const std::string& run_id, GyroColumns gyro = GyroColumns::kAll);
    ~ReplayReader();
    // Next row in recv_utime order, or nullopt at the end.
    std::optional<Row> Next();

private:
    struct Cursor;
    std::vector<std::unique_ptr<Cursor>> cursors_;
};

}  // namespace gyrocal::db
