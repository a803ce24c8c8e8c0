#include "lcmtypes/flow/flow_acker.hpp"

#include <unistd.h>

#include <chrono>

#include "gyrocal/flow_ack_t.hpp"
#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::flow {

std::string ThisHost() {
    char buf[256] = {0};
    if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
    return buf;
}

Sender::Sender(std::string process) : name(std::move(process)), host(ThisHost()), pid(getpid()) {}

FlowAcker::FlowAcker(bus::Bus& bus, std::string process) : bus_(bus), self_(std::move(process)) {
    bus_.Subscribe<flow_mark_t>(std::string(channels::kFlowMark),
                                [this](const flow_mark_t& m, const std::string&) { OnMark(m); });
}

void FlowAcker::OnMark(const flow_mark_t& m) {
    if (self_.Is(m.host, m.pid)) return;  // a source does not pace on itself
    const auto source = std::make_pair(m.host, m.pid);
    if (gate_ && !gate_()) {
        held_[source] = m.mark_seq;
        return;
    }
    held_.erase(source);
    Ack(source, m.mark_seq, false);
}

void FlowAcker::Poll() {
    if (held_.empty() || (gate_ && !gate_())) return;
    for (const auto& [source, mark_seq] : held_) Ack(source, mark_seq, false);
    held_.clear();
}

void FlowAcker::Leave() {
    // What is held was handled too (only its answer waited for room): answer it as the last.
    for (const auto& [source, mark_seq] : held_) acked_[source] = mark_seq;
    held_.clear();
    const auto sources = acked_;
    for (const auto& [source, mark_seq] : sources) Ack(source, mark_seq, true);
}

void FlowAcker::Ack(const std::pair<std::string, int32_t>& source, int64_t mark_seq, bool leaving) {
    flow_ack_t a = self_.Message<flow_ack_t>();
    a.source_host = source.first;
    a.source_pid = source.second;
    a.mark_seq = mark_seq;
    a.leaving = leaving;
    bus_.Publish(std::string(channels::kFlowAck), a);
    acked_[source] = mark_seq;
    ++acks_sent_;
}

}  // namespace gyrocal::flow
