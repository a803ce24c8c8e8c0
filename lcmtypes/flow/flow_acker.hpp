#pragma once
// The consumer side of flow control (flow_window.hpp says why): answers every flow mark it
// handles with a flow_ack_t on FLOW_ACK. Every process that runs a StatusReporter has one, so
// each gyrocal process is a consumer a source paces on, with nothing to do in its own code.
//
// Since the bus hands messages to handlers in the order they arrived, handling a mark means
// every message of that source before it has been handled. A process whose "handled" is not
// "returned from the handler" (the recorder: a row is only queued for its writer thread) sets a
// gate: marks are then answered only while the gate says there is room, from Poll().
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include "gyrocal/flow_mark_t.hpp"
#include "lcmtypes/bus/bus.hpp"

namespace gyrocal::flow {

// This host's name as every process reports it (STATUS, marks, acks).
std::string ThisHost();

// This process as its flow messages name it (flow_ack_t's `process`, flow_mark_t's `source`),
// with its host and pid, by which it also knows its own messages.
struct Sender {
    explicit Sender(std::string process);  // on ThisHost(), with this process's pid

    bool Is(const std::string& other_host, int32_t other_pid) const {
        return other_pid == pid && other_host == host;
    }
    // A message from this process, stamped now (wall clock).
    template <class Msg>
    Msg Message() const {
        Msg m{};
        m.utime = bus::WallClockUtime();
        if constexpr (requires { m.process; }) {
            m.process = name;
        } else {
            m.source = name;
        }
        m.host = host;
        m.pid = pid;
        return m;
    }

    std::string name;
    std::string host;
    int32_t pid;
};

class FlowAcker {
public:
    FlowAcker(bus::Bus& bus, std::string process);

    // While it returns false, marks are held (the newest per source) instead of answered.
    void SetGate(std::function<bool()> may_ack) { gate_ = std::move(may_ack); }
    // Answers held marks when the gate allows; cheap, call it after each dispatch.
    void Poll();
    // The last answers of a process that stops: each source it answered waits for it no more.
    void Leave();
    int64_t acks_sent() const { return acks_sent_; }

private:
    void OnMark(const flow_mark_t& m);
    void Ack(const std::pair<std::string, int32_t>& source, int64_t mark_seq, bool leaving);

    bus::Bus& bus_;
    Sender self_;
    std::function<bool()> gate_;
    std::map<std::pair<std::string, int32_t>, int64_t> held_;   // source -> newest unanswered
    std::map<std::pair<std::string, int32_t>, int64_t> acked_;  // source -> newest answered
    int64_t acks_sent_ = 0;
};

}  // namespace gyrocal::flow
