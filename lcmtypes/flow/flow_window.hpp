#pragma once
// Credit-based flow control of one non-real-time source (pure: no LCM, the time is passed in).
//
// Why: every process on an LCM multicast group receives every datagram; what a process has not
// yet read waits in its kernel socket buffer (recv_buf_size, 4 MB asked, 8 MB as the kernel
// counts it), and a datagram that arrives when that buffer is full is lost. LCM's own queue
// behind it is unbounded, so a process that reads but handles slowly grows in memory instead.
// A source that is not real time (a file, a simulation, a replay) can do better than guess a
// speed: it keeps, per consumer, at most `window_bytes` of data that the consumer has not yet
// handled on the bus. Then nothing a consumer is sent can overflow its buffers, its memory is
// bounded, and the source runs exactly as fast as the slowest consumer keeps up.
//
// The protocol: every `mark_every_bytes` the source publishes a mark (flow_mark_t: mark_seq and
// what was sent before it); each consumer answers a mark when it has handled it (flow_ack_t),
// and since a consumer handles messages in the order they arrived, the ack says "everything
// before this mark is handled". Acks are cumulative. Credit = window - the bytes published
// since the newest mark the slowest consumer acked.
//
// Bytes, not messages: the kernel charges a datagram its payload plus about a kilobyte of
// bookkeeping, so a window in "buffer bytes" (payload + kDatagramOverheadBytes) holds as well
// for one batch of 20 samples as for 20 single samples.
//
// Who the consumers are: every process that acks this source's marks, plus every process heard
// on STATUS (each gyrocal process heartbeats once a second and acks marks); a process heard on
// STATUS but not yet acking starts at what was sent when it was first heard (it cannot have
// missed more). A consumer whose ack has not advanced for `consumer_timeout_s` while it holds
// unacknowledged data is dropped from the pacing (reported by TakeEvents: a dead or stuck process
// must not stall the source forever); an ack that advances again admits it again.
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace gyrocal::flow {

using Time = std::chrono::steady_clock::time_point;

// What the kernel charges a small datagram beyond its payload (skb bookkeeping, rounded
// allocations); conservative for loopback and Ethernet.
inline constexpr int64_t kDatagramOverheadBytes = 1024;

struct WindowOptions {
    int64_t window_bytes = 2 << 20;      // [B] unacknowledged buffer bytes per consumer
    int64_t mark_every_bytes = 1 << 19;  // [B] a mark at least this often (window / 4)
    double consumer_timeout_s = 10.0;    // [s] no ack progress while owing data -> dropped
    double remark_s = 0.05;              // [s] a fresh mark this often while waiting for credit
    static WindowOptions Defaults() { return {}; }
    std::string Validate() const;  // "" or what is wrong, naming the field
};

struct ConsumerId {
    std::string host;
    int32_t pid = 0;
    bool operator<(const ConsumerId& o) const {
        return host != o.host ? host < o.host : pid < o.pid;
    }
    bool operator==(const ConsumerId& o) const { return host == o.host && pid == o.pid; }
};

// Something the source should say (stderr, STATUS): a consumer dropped or admitted again.
struct FlowEvent {
    enum class Kind { kDropped, kReadmitted, kNotAcking, kGone } kind;
    std::string process;
    ConsumerId id;
    std::string text;  // one line, e.g. "gyrocal-fitter (pid 12 on h) ..."
};

struct Mark {
    int64_t mark_seq = 0;
    int64_t sent_bytes = 0;  // [B] buffer bytes published before the mark
};

class FlowWindow {
public:
    explicit FlowWindow(WindowOptions options);

    // The source published `datagrams` more, of `payload_bytes` in all (channel names and LCM
    // headers included or not: the per-datagram overhead covers them).
    void OnPublished(int64_t datagrams, int64_t payload_bytes);
    // True when a mark is due: `mark_every_bytes` sent since the last one, or, while the source
    // waits for credit, `remark_s` since the last one (so that a late consumer can answer).
    bool MarkDue(Time now) const;
    // Records a new mark at what has been sent so far; the source publishes it.
    Mark IssueMark(Time now);

    // A consumer handled mark `mark_seq` (an ack for another source is the caller's to drop).
    void OnAck(const ConsumerId& id, const std::string& process, int64_t mark_seq, Time now);
    // A STATUS heartbeat: a process not yet known becomes an expected consumer.
    void OnHeartbeat(const ConsumerId& id, const std::string& process, Time now);
    // The consumer stops (its last ack says so): not waited for any more, and a heartbeat of the
    // same process does not bring it back.
    void OnLeave(const ConsumerId& id);
    // The consumer's process is gone (the source found no such process on its own host, e.g.
    // killed by a signal): as OnLeave, and reported.
    void OnGone(const ConsumerId& id);
    // The paced consumers that have not answered everything sent, slowest first.
    std::vector<ConsumerId> Behind() const;

    // [B] what may be published now without any consumer holding more than the window
    // unacknowledged; <= 0: wait. nullopt when there is no consumer to pace on. Drops consumers
    // past their timeout first.
    std::optional<int64_t> Credit(Time now);
    // True when every consumer being paced on has acked mark `mark_seq` (the end of the data).
    bool AllAcked(int64_t mark_seq) const;

    std::vector<FlowEvent> TakeEvents();
    // "process (pid P on H), behind B bytes" of the consumer that limits the credit; "" if none.
    std::string Slowest() const;
    int64_t sent_bytes() const { return sent_bytes_; }
    int64_t marks_issued() const { return next_mark_seq_ - 1; }
    size_t paced_consumers() const;
    int64_t dropped_total() const { return dropped_total_; }

private:
    struct Consumer {
        std::string process;
        int64_t acked_mark = 0;
        int64_t acked_bytes = 0;  // [B] sent_bytes of the newest mark it acked (or its start)
        bool acking = false;      // has answered at least one mark
        bool dropped = false;
        bool left = false;
        Time last_progress{};  // when acked_bytes last moved (or when it was first heard)
    };
    int64_t SentAtMark(int64_t mark_seq) const;  // -1 when the mark is unknown (too old or new)
    void Expire(Time now);

    WindowOptions o_;
    int64_t sent_bytes_ = 0;
    int64_t next_mark_seq_ = 1;
    int64_t last_mark_bytes_ = -1;
    Time last_mark_time_{};
    bool waiting_ = false;    // the last Credit() was <= 0
    std::deque<Mark> marks_;  // issued marks not yet acked by every consumer (bounded)
    std::map<ConsumerId, Consumer> consumers_;
    std::vector<FlowEvent> events_;
    int64_t dropped_total_ = 0;
};

}  // namespace gyrocal::flow
