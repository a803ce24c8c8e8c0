#pragma once
// A small typed layer over LCM 1.3.1, used by every process.
//
// Why it exists: the 1.3.1 C++ API has no std::function subscribe; each subscription queues 30
// messages and silently drops the rest; and a message that fails to decode (wrong type on a
// channel) only prints to stderr. Here every subscription is a raw one with an unbounded queue
// (capacity 0 = unlimited in LCM), decoding happens in our code so failures are counted, and
// every message type with a `seq` field feeds a per-channel SeqTracker so network loss is
// counted. A handler's exception is never thrown through LCM's C stack: it is recorded, counted
// per channel (handler_errors), the other subscribers of the same message still get it, and the
// first is rethrown from Handle() once LCM has returned.
//
// Threads: none of its own. LCM's receive thread queues packets; Handle() dispatches them on the
// caller's thread.
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lcmtypes/bus/batch.hpp"
#include "lcmtypes/bus/decode.hpp"
#include "lcmtypes/bus/seq_tracker.hpp"

namespace gyrocal::bus {

// The default URL: LCM's group and port, TTL 0 (never leaves this host) and a 4 MB receive
// buffer, so that bursts are not dropped by the kernel (its measured throughput:
// producers/sim_rig/README.md#benchmark-the-simulated-rig-and-the-bus).
inline constexpr const char* kDefaultLcmUrl =
    "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

struct BusOptions {
    std::string url;  // LCM provider URL; "" = $GYROCAL_LCM_URL, else kDefaultLcmUrl
    static BusOptions Defaults() { return {}; }
    std::string ResolvedUrl() const;
};

// The multicast group and port of a udpm:// URL (LCM's default port 7667 when it names none):
// what tells one bus from another (a lab's chambers use one port each; TTL and buffer options do
// not make another bus). nullopt for any other provider or a malformed URL.
struct UdpmAddress {
    std::string group;  // dotted IPv4, e.g. "239.255.76.67"
    int port = 7667;
    std::string options;  // what follows '?', without it ("" when none)
    bool operator==(const UdpmAddress& o) const { return group == o.group && port == o.port; }
};
std::optional<UdpmAddress> ParseUdpm(const std::string& url);
std::string FormatUdpm(const UdpmAddress& a);  // back to a URL, options kept

// Thrown when LCM cannot be opened; what() says what to do about it.
class BusError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct BusCounters {
    int64_t received = 0;  // decoded and handed to a handler
    int64_t published = 0;
    int64_t published_bytes = 0;  // [B] payloads and channel names of what was published
    int64_t publish_errors = 0;
    int64_t decode_errors = 0;      // payload did not decode as the subscribed type
    int64_t batches = 0;            // batch messages unpacked (their samples count in received)
    int64_t seq_gaps = 0;           // samples missing per seq, all channels
    int64_t seq_backwards = 0;      // reordered, duplicated or restarted streams
    std::string last_decode_error;  // channel and type of the latest failure
    // A handler threw (the message was still given to the channel's other subscribers).
    int64_t handler_errors = 0;
    std::map<std::string, int64_t> handler_errors_by_channel;
    std::string first_handler_error;  // channel and what() of the first
};

class Bus {
public:
    using RawHandler = std::function<void(const lcm::ReceiveBuffer&, const std::string& channel)>;

    explicit Bus(const BusOptions& options = BusOptions::Defaults());
    Bus(const Bus&) = delete;
    Bus& operator=(const Bus&) = delete;
    ~Bus();

    // Subscribes a typed handler to every channel matching `channel_regex`. Messages that do not
    // decode as Msg are counted (decode_errors) and never reach the handler. For a sample type
    // with a batch form (batch.hpp: gyro, encoder, rate), a batch on the channel is unpacked and
    // the handler called once per sample, in order, each counted and seq-tracked as if it had
    // come alone.
    template <class Msg>
    void Subscribe(const std::string& channel_regex,
                   std::function<void(const Msg&, const std::string& channel)> handler);

    // Subscribes to raw bytes (the recorder's unknown-type fallback, log tools).
    void SubscribeRaw(const std::string& channel_regex, RawHandler handler);

    // Encodes and publishes; counts failures (LCM returns non-zero when the send fails).
    template <class Msg>
    bool Publish(const std::string& channel, const Msg& msg);
    // Publishes samples of one channel: one Msg when there is one, else their batch form
    // (batch.hpp). Nothing when empty.
    template <class Msg>
    bool PublishSamples(const std::string& channel, std::vector<Msg> samples);
    bool PublishRaw(const std::string& channel, const void* data, int size);

    // Dispatches messages for up to `timeout`; returns true when at least one was handled.
    // Rethrows the first exception a handler raised (after LCM has returned and every other
    // subscriber of that message has had it); every one is counted in handler_errors.
    bool Handle(std::chrono::milliseconds timeout);

    const BusCounters& counters() const { return counters_; }
    const SeqTracker& seq() const { return seq_; }
    const std::string& url() const { return url_; }

private:
    struct Subscriber {
        Bus* bus;
        RawHandler fn;
        void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
    };
    void AddSubscription(const std::string& channel_regex, RawHandler fn);
    void NoteSeq(const std::string& channel, int64_t seq);
    template <class Msg, class Handler>
    void Deliver(const Msg& msg, const std::string& channel, const Handler& handler);
    // Decodes `rbuf` as a T (a message or its batch); false, counted as a decode error that names
    // the channel and the type, when it is not one.
    template <class T>
    bool DecodeCounted(T& out, const lcm::ReceiveBuffer& rbuf, const std::string& channel);

    std::string url_;
    std::unique_ptr<lcm::LCM> lcm_;
    std::vector<std::unique_ptr<Subscriber>> subscribers_;
    BusCounters counters_;
    SeqTracker seq_;
    std::exception_ptr pending_;
};

// [us] since 1970 by the wall clock, now: the utime of a message stamped as it is sent (STATUS,
// flow marks and answers, the launcher's run events) and of a line read from a live stream.
int64_t WallClockUtime();

template <class Msg, class Handler>
void Bus::Deliver(const Msg& msg, const std::string& channel, const Handler& handler) {
    ++counters_.received;
    if constexpr (requires { msg.seq; }) NoteSeq(channel, msg.seq);
    handler(msg, channel);
}

template <class T>
bool Bus::DecodeCounted(T& out, const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
    if (DecodeMessage(out, rbuf.data, static_cast<int>(rbuf.data_size))) return true;
    ++counters_.decode_errors;
    counters_.last_decode_error =
        "channel " + channel + ": payload is not a valid " + T::getTypeName();
    return false;
}

template <class Msg>
void Bus::Subscribe(const std::string& channel_regex,
                    std::function<void(const Msg&, const std::string& channel)> handler) {
    AddSubscription(channel_regex, [this, handler = std::move(handler)](
                                       const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
        if constexpr (HasBatch<Msg>) {
            using Batch = typename BatchTraits<Msg>::Batch;
            if (IsOfType<Batch>(rbuf.data, static_cast<int>(rbuf.data_size))) {
                Batch batch;
                if (!DecodeCounted(batch, rbuf, channel)) return;
                ++counters_.batches;
                for (const Msg& msg : batch.samples) Deliver(msg, channel, handler);
                return;
            }
        }
        Msg msg;
        if (DecodeCounted(msg, rbuf, channel)) Deliver(msg, channel, handler);
    });
}

template <class Msg>
bool Bus::Publish(const std::string& channel, const Msg& msg) {
    const int size = msg.getEncodedSize();
    std::vector<uint8_t> buf(static_cast<size_t>(size));
    if (msg.encode(buf.data(), 0, size) < 0) {
        throw std::logic_error("cannot encode " + std::string(Msg::getTypeName()) + " for " +
                               channel + " (array length field does not match its array?)");
    }
    return PublishRaw(channel, buf.data(), size);
}

template <class Msg>
bool Bus::PublishSamples(const std::string& channel, std::vector<Msg> samples) {
    if (samples.empty()) return true;
    if (samples.size() == 1) return Publish(channel, samples.front());
    return Publish(channel, MakeBatch<typename BatchTraits<Msg>::Batch>(std::move(samples)));
}

}  // namespace gyrocal::bus
