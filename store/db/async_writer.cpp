#include "store/db/async_writer.hpp"

#include <array>
#include <map>

namespace gyrocal::db {

namespace {

// The table each kind of row goes to, in the order of the Row variant.
constexpr std::array<const char*, std::variant_size_v<Row>> kTables = {
    "gyro_samples",   "encoder_samples", "chamber_states",     "chamber_cmds", "turntable_cmds",
    "plateau_states", "plateaus",        "sensitivity_points", "coeff_sets",   "rates",
    "status",         "run_events",      "raw_events"};

const std::string& RunOf(const Row& row) {
    return std::visit([](const auto& r) -> const std::string& { return r.run_id; }, row);
}

}  // namespace

std::string SummarizeRows(const std::vector<Row>& rows) {
    std::map<std::pair<std::string, std::string>, int64_t> n;
    for (const Row& r : rows) ++n[{RunOf(r), kTables[r.index()]}];
    std::string out;
    for (const auto& [key, count] : n) {
        out += (out.empty() ? "" : ", ") + (key.first.empty() ? "(no run)" : key.first) + " " +
               key.second + " " + std::to_string(count);
    }
    return out;
}

AsyncWriter::AsyncWriter(StoreWriter& writer, AsyncWriterOptions options)
    : writer_(writer), options_(options) {
    if (options_.batch_rows == 0) options_.batch_rows = 1;
    queue_.reserve(options_.batch_rows);
    thread_ = std::thread([this] { Loop(); });
}

AsyncWriter::~AsyncWriter() { Stop(); }

bool AsyncWriter::Push(Row&& row, const std::string& channel, bool essential) {
    std::unique_lock lock(mu_);
    if (failed_.load() || (!essential && queue_.size() + in_flight_ >= options_.queue_rows)) {
        ++stats_.dropped;
        ++losses_[{RunOf(row), channel}].queue_drops;
        return false;
    }
    if (queue_.empty()) oldest_ = std::chrono::steady_clock::now();
    queue_.push_back(std::move(row));
    ++stats_.pushed;
    const size_t n = queue_.size();
    if (static_cast<int64_t>(n) > stats_.max_queue_rows)
        stats_.max_queue_rows = static_cast<int64_t>(n);
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
    AsyncWriterStats s = stats_;
    s.held_rows = static_cast<int64_t>(queue_.size() + in_flight_);
    return s;
}

void AsyncWriter::WaitForWork(std::unique_lock<std::mutex>& lock, bool retrying) {
    if (retrying) {  // a storage fault: try again at the retry time (or at once on Stop())
        cv_.wait_until(lock, next_retry_, [this] { return stop_; });
        return;
    }
    // Wake for a full batch, for the age of the oldest row, or to stop. Loss deltas alone wait
    // for the interval too.
    for (;;) {
        if (stop_ || queue_.size() >= options_.batch_rows) return;
        const auto now = std::chrono::steady_clock::now();
        if (!queue_.empty() && now - oldest_ >= options_.batch_interval) return;
        if (queue_.empty() && !losses_.empty()) {
            cv_.wait_for(lock, options_.batch_interval);
            return;
        }
        if (queue_.empty()) {
            cv_.wait_for(lock, options_.batch_interval);
        } else {
            cv_.wait_until(lock, oldest_ + options_.batch_interval);
        }
    }
}

void AsyncWriter::Loop() {
    std::vector<Row> batch;  // taken from the queue, not yet committed
    LossMap losses;          // loss deltas not yet committed
    batch.reserve(options_.batch_rows);
    for (;;) {
        bool stopping = false;
        {
            std::unique_lock lock(mu_);
            WaitForWork(lock, !batch.empty() || !losses.empty());
            stopping = stop_;
            if (batch.empty()) {
                batch.swap(queue_);
            } else {  // still held after a storage fault: what arrived since goes after it
                batch.insert(batch.end(), std::make_move_iterator(queue_.begin()),
                             std::make_move_iterator(queue_.end()));
                queue_.clear();
            }
            for (const auto& [key, d] : losses_) losses[key] += d;
            losses_.clear();
            queue_.reserve(options_.batch_rows);
            in_flight_ = batch.size();
        }
        if (!batch.empty() || !losses.empty()) {
            if (TryWrite(batch, losses, stopping)) {
                batch.clear();
                losses.clear();
                std::lock_guard lock(mu_);
                in_flight_ = 0;
            } else if (failed_.load()) {
                return;
            }
        }
        if (stopping) {
            std::lock_guard lock(mu_);
            if (queue_.empty() && losses_.empty()) return;
        }
    }
}

bool AsyncWriter::TryWrite(const std::vector<Row>& batch, const LossMap& losses,
                           bool last_attempt) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    std::string fault;  // StorageFaultName, "" when not a storage fault
    try {
        writer_.Write(batch, losses);
    } catch (const StoreError& e) {
        error = e.what();
        if (IsStorageFault(e.sqlite_code())) fault = StorageFaultName(e);
        const bool storage_fault = !fault.empty();
        if (storage_fault && !last_attempt) {
            std::lock_guard lock(mu_);
            if (!stats_.blocked) {
                stats_.blocked = true;
                stats_.blocked_since = t0;
                ++stats_.fault_episodes;
            }
            stats_.blocked_reason = fault;
            stats_.blocked_error = error;
            ++stats_.failed_writes;
            next_retry_ = std::chrono::steady_clock::now() + options_.retry_interval;
            return false;
        }
    } catch (const std::exception& e) {
        error = e.what();
    }
    std::lock_guard lock(mu_);
    if (!error.empty()) {  // not a storage fault, or still one at Stop(): give up what is held
        std::vector<Row> held = batch;
        held.insert(held.end(), queue_.begin(), queue_.end());
        stats_.unwritten_rows = static_cast<int64_t>(held.size());
        stats_.unwritten_summary = SummarizeRows(held);
        error_ = fault.empty()
                     ? error
                     : "the database still cannot be written at stop (" + fault + "): " + error;
        failed_.store(true);
        return false;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    stats_.written += static_cast<int64_t>(batch.size());
    ++stats_.batches;
    if (ms > stats_.max_commit_ms) stats_.max_commit_ms = ms;
    stats_.blocked = false;
    stats_.blocked_reason.clear();
    stats_.blocked_error.clear();
    return true;
}

}  // namespace gyrocal::db
