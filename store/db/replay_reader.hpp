#pragma once
// Reads a stored run back in reception order, for gyrocal-replay.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::store {

// Streams the replayable messages of a run (gyro, encoder, chamber state, run events, power) in
// reception order (merged by recv_utime). Throws NotFound.
class ReplayReader {
public:
    ReplayReader(Db& db, const std::string& run_id);
    ~ReplayReader();
    // Next row in recv_utime order, or nullopt at the end.
    std::optional<Row> Next();

private:
    struct Cursor;
    std::vector<std::unique_ptr<Cursor>> cursors_;
};

}  // namespace gyrocal::store
