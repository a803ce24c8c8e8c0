#include "store/recorder/writer_watch.hpp"

#include "lcmtypes/text/number.hpp"

namespace gyrocal::recorder {

namespace {

double Seconds(std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

std::string StateWord(const std::string& fault) {
    std::string s = fault;
    for (char& c : s) {
        if (c == ' ') c = '_';
    }
    return "db_blocked:" + s;
}

}  // namespace

WriterWatch::WriterWatch(size_t bound_rows, std::chrono::seconds repeat)
    : bound_rows_(bound_rows), repeat_(repeat) {}

WatchReport WriterWatch::Update(const db::AsyncWriterStats& s, Clock::time_point now) {
    WatchReport r;
    const double blocked_s = s.blocked ? Seconds(now - s.blocked_since) : 0.0;
    r.state = s.blocked ? StateWord(s.blocked_reason) : "recording";
    r.extras = {{"rows_written", static_cast<double>(s.written)},
                {"batches", static_cast<double>(s.batches)},
                {"max_queue_rows", static_cast<double>(s.max_queue_rows)},
                {"max_commit_ms", s.max_commit_ms},
                {"held_rows", static_cast<double>(s.held_rows)},
                {"held_bound_rows", static_cast<double>(bound_rows_)},
                {"rows_dropped", static_cast<double>(s.dropped)},
                {"db_failed_writes", static_cast<double>(s.failed_writes)},
                {"db_blocked_s", blocked_s}};
    const std::string held = std::to_string(s.held_rows) + " rows in memory (bound " +
                             std::to_string(bound_rows_) + " rows, --queue-rows)";
    if (s.blocked && !blocked_) {
        blocked_ = true;
        dropped_at_block_ = s.dropped;
        written_at_block_ = s.written;
        since_ = s.blocked_since;
        last_log_ = now;
        r.log.push_back("database writes fail (" + s.blocked_reason + "): " + s.blocked_error +
                        "; keeping rows in memory and trying again every second; " + held);
    } else if (s.blocked && now - last_log_ >= repeat_) {
        last_log_ = now;
        r.log.push_back("database still failing (" + s.blocked_reason + ") after " +
                        text::Printf("%.1f", blocked_s) + " s: " + held + ", " +
                        std::to_string(s.dropped - dropped_at_block_) + " dropped at the bound");
    } else if (!s.blocked && blocked_) {
        blocked_ = false;
        r.log.push_back("database writable again after " +
                        text::Printf("%.1f", Seconds(now - since_)) +
                        " s: " + std::to_string(s.written - written_at_block_) +
                        " rows written since the fault began, " +
                        std::to_string(s.dropped - dropped_at_block_) +
                        " dropped at the bound (stored in losses.queue_drops by run and channel)");
    }
    return r;
}

}  // namespace gyrocal::recorder
