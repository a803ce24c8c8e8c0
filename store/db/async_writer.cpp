#include "async_writer.hpp"

namespace gyrocal::store {

AsyncWriter::AsyncWriter(StoreWriter& writer, AsyncWriterOptions options)
    : writer_(writer), options_(options) {
    if (options_.batch_rows == 0) options_.batch_rows = 1;
    queue_.reserve(options_.batch_rows);
    thread_ = std::thread([this] { Loop(); });
}

AsyncWriter::~AsyncWriter() { Stop(); }

bool AsyncWriter::Push(Row&& row, const std::string& channel, bool essential) {
    std::unique_lock lock(mu_);
    if (failed_.load() || (!essential && queue_.size() >= options_.queue_rows)) {
        ++stats_.dropped;
        const std::string& run_id = std::visit([](const auto& r) -> const std::string& {
            return r.run_id;
        }, row);
        ++losses_[{run_id, channel}].queue_drops;
        return false;
    }
    if (queue_.empty()) oldest_ = std::chrono::steady_clock::now();
    queue_.push_back(std::move(row));
    ++stats_.pushed;
    const size_t n = queue_.size();
    if (static_cast<int64_t>(n) > stats_.max_queue_rows) stats_.max_queue_rows = static_cast<int64_t>(n);
    lock.unlock();
    if (n == options_.batch_rows) cv_.notify_one();
    return true;
}

void AsyncWriter::AddLoss(const std::string& run_id, const std::string& channel,
                          const LossDelta& delta) {
    if (delta.Empty()) return;
    std::lock_guard lock(mu_);
    losses_[{run_id, channel}] += delta;
}

void AsyncWriter::Stop() {
    {
        std::lock_guard lock(mu_);
        stop_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
}

std::string AsyncWriter::error() const {
    std::lock_guard lock(mu_);
    return error_;
}

AsyncWriterStats AsyncWriter::stats() const {
    std::lock_guard lock(mu_);
    return stats_;
}

void AsyncWriter::Loop() {
    std::vector<Row> batch;
    batch.reserve(options_.batch_rows);
    LossMap losses;
    for (;;) {
        bool stopping = false;
        {
            std::unique_lock lock(mu_);
            // Wake for a full batch, for the age of the oldest row, or to stop. Loss deltas alone
            // wait for the interval too.
            for (;;) {
                if (stop_ || queue_.size() >= options_.batch_rows) break;
                const auto now = std::chrono::steady_clock::now();
                if (!queue_.empty() && now - oldest_ >= options_.batch_interval) break;
                if (queue_.empty() && !losses_.empty()) {
                    cv_.wait_for(lock, options_.batch_interval);
                    break;
                }
                if (queue_.empty()) {
                    cv_.wait_for(lock, options_.batch_interval);
                } else {
                    cv_.wait_until(lock, oldest_ + options_.batch_interval);
                }
            }
            stopping = stop_;
            batch.swap(queue_);
            losses.swap(losses_);
            queue_.reserve(options_.batch_rows);
        }
        if (!batch.empty() || !losses.empty()) {
            const auto t0 = std::chrono::steady_clock::now();
            try {
                writer_.Write(batch, losses);
            } catch (const std::exception& e) {
                std::lock_guard lock(mu_);
                error_ = e.what();
                failed_.store(true);
                stats_.dropped += static_cast<int64_t>(batch.size());
                return;
            }
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            std::lock_guard lock(mu_);
            stats_.written += static_cast<int64_t>(batch.size());
            ++stats_.batches;
            if (ms > stats_.max_commit_ms) stats_.max_commit_ms = ms;
        }
        batch.clear();
        losses.clear();
        if (stopping) {
            std::lock_guard lock(mu_);
            if (queue_.empty() && losses_.empty()) return;
        }
    }
}

}  // namespace gyrocal::store
