#include "lcmtypes/flow/flow_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gyrocal::flow {

namespace {
// Marks kept to translate an ack into bytes; older ones are forgotten (an ack of a forgotten
// mark counts as the oldest one kept, which is never more than the truth).
constexpr size_t kMaxMarks = 4096;

std::string Who(const std::string& process, const ConsumerId& id) {
    return process + " (pid " + std::to_string(id.pid) + " on " + id.host + ")";
}
}  // namespace

std::string WindowOptions::Validate() const {
    if (!(window_bytes >= 4 * kDatagramOverheadBytes && window_bytes <= (int64_t{1} << 34)))
        return "window_bytes " + std::to_string(window_bytes) + " out of range 4096..2^34";
    if (!(mark_every_bytes >= 1 && mark_every_bytes <= window_bytes))
        return "mark_every_bytes must be in 1..window_bytes";
    if (!(consumer_timeout_s > 0 && consumer_timeout_s <= 3600))
        return "consumer_timeout_s must be in (0, 3600] s";
    if (!(remark_s > 0 && remark_s <= 10)) return "remark_s must be in (0, 10] s";
    return "";
}

FlowWindow::FlowWindow(WindowOptions options) : o_(options) {}

void FlowWindow::OnPublished(int64_t datagrams, int64_t payload_bytes) {
    sent_bytes_ += std::max<int64_t>(0, payload_bytes) +
                   std::max<int64_t>(0, datagrams) * kDatagramOverheadBytes;
}

bool FlowWindow::MarkDue(Time now) const {
    if (last_mark_bytes_ < 0) return true;
    if (sent_bytes_ - last_mark_bytes_ >= o_.mark_every_bytes) return true;
    return waiting_ && std::chrono::duration<double>(now - last_mark_time_).count() >= o_.remark_s;
}

Mark FlowWindow::IssueMark(Time now) {
    const Mark m{next_mark_seq_++, sent_bytes_};
    marks_.push_back(m);
    if (marks_.size() > kMaxMarks) marks_.pop_front();
    last_mark_bytes_ = sent_bytes_;
    last_mark_time_ = now;
    return m;
}

int64_t FlowWindow::SentAtMark(int64_t mark_seq) const {
    if (marks_.empty() || mark_seq > marks_.back().mark_seq) return -1;
    if (mark_seq < marks_.front().mark_seq) return marks_.front().sent_bytes;
    return marks_[static_cast<size_t>(mark_seq - marks_.front().mark_seq)].sent_bytes;
}

void FlowWindow::OnAck(const ConsumerId& id, const std::string& process, int64_t mark_seq,
                       Time now) {
    const int64_t at = SentAtMark(mark_seq);
    if (at < 0) return;  // not a mark of ours (a stale ack from before a restart)
    auto [it, added] = consumers_.try_emplace(id);
    Consumer& c = it->second;
    if (added) c.last_progress = now;
    if (c.left) return;
    c.process = process;
    c.acking = true;
    if (mark_seq <= c.acked_mark && !added) return;
    c.acked_mark = mark_seq;
    if (at > c.acked_bytes || added) {
        c.acked_bytes = at;
        c.last_progress = now;
    }
    if (c.dropped) {
        c.dropped = false;
        events_.push_back({FlowEvent::Kind::kReadmitted, process, id,
                           Who(process, id) + " acks again: paced on again"});
    }
}

void FlowWindow::OnHeartbeat(const ConsumerId& id, const std::string& process, Time now) {
    auto [it, added] = consumers_.try_emplace(id);
    if (!added) return;
    // It cannot have missed what was sent before it was heard; it owes what comes after.
    it->second.process = process;
    it->second.acked_bytes = sent_bytes_;
    it->second.last_progress = now;
}

void FlowWindow::OnLeave(const ConsumerId& id) { consumers_[id].left = true; }

void FlowWindow::OnGone(const ConsumerId& id) {
    Consumer& c = consumers_[id];
    if (c.left) return;
    c.left = true;
    events_.push_back({FlowEvent::Kind::kGone, c.process, id,
                       Who(c.process, id) + " has ended (no such process) owing " +
                           std::to_string(sent_bytes_ - c.acked_bytes) +
                           " B: no longer waited for"});
}

std::vector<ConsumerId> FlowWindow::Behind() const {
    std::vector<std::pair<int64_t, ConsumerId>> behind;
    for (const auto& [id, c] : consumers_)
        if (!c.dropped && !c.left && c.acked_bytes < sent_bytes_)
            behind.push_back({c.acked_bytes, id});
    std::sort(behind.begin(), behind.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<ConsumerId> out;
    for (const auto& [bytes, id] : behind) out.push_back(id);
    return out;
}

void FlowWindow::Expire(Time now) {
    for (auto& [id, c] : consumers_) {
        if (c.dropped || c.left || c.acked_bytes >= sent_bytes_) continue;
        const double silent_s = std::chrono::duration<double>(now - c.last_progress).count();
        if (silent_s < o_.consumer_timeout_s) continue;
        c.dropped = true;
        ++dropped_total_;
        const bool never = !c.acking;
        const std::string why = never ? " heartbeats on STATUS but has not answered a flow mark"
                                      : " has not acknowledged data";
        events_.push_back({never ? FlowEvent::Kind::kNotAcking : FlowEvent::Kind::kDropped,
                           c.process, id,
                           Who(c.process, id) + why + " for " +
                               std::to_string(static_cast<int>(std::lround(silent_s))) +
                               " s: no longer waited for (it may lose messages, counted by its "
                               "sequence gaps)"});
    }
}

std::optional<int64_t> FlowWindow::Credit(Time now) {
    Expire(now);
    int64_t behind = -1;
    for (const auto& [id, c] : consumers_) {
        if (c.dropped || c.left) continue;
        behind = std::max(behind, sent_bytes_ - c.acked_bytes);
    }
    if (behind < 0) {
        waiting_ = false;
        return std::nullopt;
    }
    const int64_t credit = o_.window_bytes - behind;
    waiting_ = credit <= 0;
    return credit;
}

bool FlowWindow::AllAcked(int64_t mark_seq) const {
    for (const auto& [id, c] : consumers_) {
        if (c.dropped || c.left) continue;
        if (c.acked_mark < mark_seq) return false;
    }
    return true;
}

std::vector<FlowEvent> FlowWindow::TakeEvents() {
    std::vector<FlowEvent> out;
    out.swap(events_);
    return out;
}

std::string FlowWindow::Slowest() const {
    const Consumer* slow = nullptr;
    const ConsumerId* slow_id = nullptr;
    for (const auto& [id, c] : consumers_) {
        if (c.dropped || c.left) continue;
        if (!slow || c.acked_bytes < slow->acked_bytes) {
            slow = &c;
            slow_id = &id;
        }
    }
    if (!slow) return "";
    return Who(slow->process, *slow_id) + ", behind " +
           std::to_string(sent_bytes_ - slow->acked_bytes) + " B";
}

size_t FlowWindow::paced_consumers() const {
    return static_cast<size_t>(
        std::count_if(consumers_.begin(), consumers_.end(),
                      [](const auto& kv) { return !kv.second.dropped && !kv.second.left; }));
}

}  // namespace gyrocal::flow
