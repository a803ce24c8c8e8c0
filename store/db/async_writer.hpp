#pragma once
// AsyncWriter: a bounded row queue drained by one writer thread into a StoreWriter.
//
// Threads: producers (the recorder's LCM handler thread) only call Push()/AddLoss(), which take
// a mutex for a vector push_back. The writer thread wakes when `batch_rows` rows are queued or
// `batch_interval` has passed since the oldest queued row arrived, swaps the queue out and writes
// it, with the loss deltas accumulated meanwhile, in one transaction.
//
// Loss bound: a row pushed at time t is committed by t + batch_interval + (time of one commit),
// as long as the writer keeps up. A SIGKILL therefore loses at most the rows pushed in the last
// batch_interval plus one commit duration (and whatever the queue held if the writer had fallen
// behind, which the queue bound caps at `queue_rows` rows).
//
// Memory bound: at most `queue_rows` rows are held, counting the queue and the batch the writer
// has taken. When the bound is reached, Push() drops the row and counts it as a queue drop of its
// run and channel (stored in losses with the next batch that commits). Essential rows (run
// events, coefficient sets: few, and the run structure depends on them) are never dropped.
//
// Storage faults (disk full, file or file system read-only, locked by another writer, I/O error:
// IsStorageFault): the batch that failed is kept, with its loss deltas, and written again every
// `retry_interval` (StoreWriter reopens the file first) together with what arrived meanwhile,
// until it commits; nothing is lost up to the memory bound. stats().blocked says so, with the
// reason. On Stop() while blocked, one last attempt is made; if it fails the rows still held are
// given up and counted (unwritten_rows, unwritten_summary) and failed() becomes true.
// Any other failure (a corrupt file, a bug) stops the writer at once: failed() and error().
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/writer.hpp"

namespace gyrocal::db {

struct AsyncWriterOptions {
    size_t queue_rows = 100000;  // rows held in memory (queued or waiting) before Push() drops
    size_t batch_rows = 1000;    // commit at least this often (rows)
    std::chrono::milliseconds batch_interval{200};   // ... and at least this often (time)
    std::chrono::milliseconds retry_interval{1000};  // while a storage fault lasts
    static AsyncWriterOptions Defaults() { return {}; }
};

struct AsyncWriterStats {
    int64_t pushed = 0;   // rows accepted
    int64_t dropped = 0;  // rows dropped because the memory bound was reached (or failure)
    int64_t written = 0;  // rows committed
    int64_t batches = 0;  // transactions committed
    int64_t max_queue_rows = 0;
    double max_commit_ms = 0;  // slowest transaction
    int64_t held_rows = 0;     // rows in memory now, not yet committed
    // Storage faults.
    bool blocked = false;        // the last write failed with a storage fault; retrying
    std::string blocked_reason;  // StorageFaultName: "disk full", "read-only", ...
    std::string blocked_error;   // the whole error of the last failed attempt
    int64_t failed_writes = 0;   // attempts that failed with a storage fault
    int64_t fault_episodes = 0;  // times the writer became blocked
    std::chrono::steady_clock::time_point blocked_since{};
    int64_t unwritten_rows = 0;     // given up at Stop() while still blocked
    std::string unwritten_summary;  // e.g. "R1 gyro_samples 4000, R1 status 12"
};

class AsyncWriter {
public:
    AsyncWriter(StoreWriter& writer, AsyncWriterOptions options);
    ~AsyncWriter();  // Stop()s
    AsyncWriter(const AsyncWriter&) = delete;
    AsyncWriter& operator=(const AsyncWriter&) = delete;

    // Queues a row; returns false (and counts a queue drop for run/channel) when full.
    bool Push(Row&& row, const std::string& channel, bool essential = false);
    // Adds loss counts for (run_id, channel); written with the next batch, never dropped.
    void AddLoss(const std::string& run_id, const std::string& channel, const LossDelta& delta);
    // Writes everything held (one last attempt when blocked), then ends the thread. Idempotent.
    void Stop();

    // True after a failure that is not a storage fault, or rows given up at Stop().
    bool failed() const { return failed_.load(); }
    std::string error() const;
    AsyncWriterStats stats() const;

private:
    void Loop();
    // Waits for work: a full batch, the age of the oldest row, the retry time, or Stop().
    void WaitForWork(std::unique_lock<std::mutex>& lock, bool retrying);
    // One write of `batch` + `losses`; true when committed. A storage fault keeps them (blocked);
    // any other failure sets failed_.
    bool TryWrite(const std::vector<Row>& batch, const LossMap& losses, bool last_attempt);

    StoreWriter& writer_;
    AsyncWriterOptions options_;
    mutable std::mutex mu_;
    std::condition_variable cv_;
    std::vector<Row> queue_;
    LossMap losses_;
    size_t in_flight_ = 0;  // rows the writer thread holds (being written or waiting to retry)
    std::chrono::steady_clock::time_point oldest_{};
    std::chrono::steady_clock::time_point next_retry_{};
    bool stop_ = false;
    std::atomic<bool> failed_{false};
    std::string error_;
    AsyncWriterStats stats_;
    std::thread thread_;
};

// "R1 gyro_samples 4000, R1 status 12": the rows by run and table, for messages.
std::string SummarizeRows(const std::vector<Row>& rows);

}  // namespace gyrocal::db
