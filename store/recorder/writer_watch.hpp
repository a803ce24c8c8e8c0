#pragma once
// WriterWatch: what gyrocal-recorder says about its database writer, from AsyncWriter's stats:
// the STATUS state and counters, and the lines for its log (stderr):
// - when writes start failing with a storage fault: the fault, the error, the memory bound;
// - every `repeat` while it lasts: for how long, rows in memory, rows dropped at the bound;
// - when a write succeeds again: after how long, rows written from memory, rows dropped (which
//   are in losses.queue_drops of their run and channel).
// STATUS state: "recording", or "db_blocked:<fault>" (disk_full, read-only, locked_by_another_
// writer, I/O_error, cannot_open) while a storage fault lasts; the recorder sets "failed" itself.
// Pure: the time is passed in.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "store/db/async_writer.hpp"

namespace gyrocal::recorder {

struct WatchReport {
    std::string state;
    std::vector<std::pair<std::string, double>> extras;  // STATUS extra counters
    std::vector<std::string> log;                        // lines for stderr, may be empty
};

class WriterWatch {
public:
    using Clock = std::chrono::steady_clock;
    explicit WriterWatch(size_t bound_rows, std::chrono::seconds repeat = std::chrono::seconds(10));

    WatchReport Update(const db::AsyncWriterStats& s, Clock::time_point now);

private:
    size_t bound_rows_;
    std::chrono::seconds repeat_;
    bool blocked_ = false;
    int64_t dropped_at_block_ = 0;
    int64_t written_at_block_ = 0;
    Clock::time_point since_{};  // the fault began (first failed write)
    Clock::time_point last_log_{};
};

}  // namespace gyrocal::recorder
