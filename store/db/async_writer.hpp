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
// Overflow: when `queue_rows` rows are waiting, Push() drops the row and counts it as a
// queue drop of its run and channel (stored in losses). Essential rows (run events, coefficient
// sets: few, and the run structure depends on them) are never dropped.
//
// Failure: if a write fails (disk full, file removed...), the writer thread stops, failed()
// becomes true and error() says why; further pushes are counted as drops.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rows.hpp"
#include "writer.hpp"

namespace gyrocal::store {

struct AsyncWriterOptions {
    size_t queue_rows = 100000;   // rows waiting before Push() drops (~55 MB at most)
    size_t batch_rows = 1000;     // commit at least this often (rows)
    std::chrono::milliseconds batch_interval{200};  // ... and at least this often (time)
    static AsyncWriterOptions Defaults() { return {}; }
};

struct AsyncWriterStats {
    int64_t pushed = 0;       // rows accepted
    int64_t dropped = 0;      // rows dropped because the queue was full (or the writer failed)
    int64_t written = 0;      // rows committed
    int64_t batches = 0;      // transactions committed
    int64_t max_queue_rows = 0;
    double max_commit_ms = 0; // slowest transaction
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
    // Writes everything queued, then ends the thread. Idempotent.
    void Stop();

    bool failed() const { return failed_.load(); }
    std::string error() const;
    AsyncWriterStats stats() const;

private:
    void Loop();

    StoreWriter& writer_;
    AsyncWriterOptions options_;
    mutable std::mutex mu_;
    std::condition_variable cv_;
    std::vector<Row> queue_;
    LossMap losses_;
    std::chrono::steady_clock::time_point oldest_{};
    bool stop_ = false;
    std::atomic<bool> failed_{false};
    std::string error_;
    AsyncWriterStats stats_;
    std::thread thread_;
};

}  // namespace gyrocal::store
