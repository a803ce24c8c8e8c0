#pragma once
// A small typed layer over LCM 1.3.1, used by every process.
//
// Why it exists: the 1.3.1 C++ API has no std::function subscribe; each subscription queues 30
// messages and silently drops the rest; and a message that fails to decode (wrong type on a
// channel) only prints to stderr. Here every subscription is a raw one with an unbounded queue
// (capacity 0 = unlimited in LCM), decoding happens in our code so failures are counted, and
// every message type with a `seq` field feeds a per-channel SeqTracker so network loss is
// counted. A handler's exception is never thrown through LCM's C stack: it is recorded and
// rethrown from Handle() once LCM has returned.
//
// Threads: none of its own. LCM's receive thread queues packets; Handle() dispatches them on the
// caller's thread.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "decode.hpp"
#include "seq_tracker.hpp"

namespace gyrocal {

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
    int64_t received = 0;       // decoded and handed to a handler
    int64_t published = 0;
    int64_t publish_errors = 0;
    int64_t decode_errors = 0;  // payload did not decode as the subscribed type
    int64_t seq_gaps = 0;       // samples missing per seq, all channels
    int64_t seq_backwards = 0;  // reordered, duplicated or restarted streams
    std::string last_decode_error;  // channel and type of the latest failure
};

class Bus {
public:
    using RawHandler = std::function<void(const lcm::ReceiveBuffer&, const std::string& channel)>;

    explicit Bus(const BusOptions& options = BusOptions::Defaults());
    Bus(const Bus&) = delete;
    Bus& operator=(const Bus&) = delete;
    ~Bus();

    // Subscribes a typed handler to every channel matching `channel_regex`. Messages that do not
    // decode as Msg are counted (decode_errors) and never reach the handler.
    template <class Msg>
    void Subscribe(const std::string& channel_regex,
                   std::function<void(const Msg&, const std::string& channel)> handler);

    // Subscribes to raw bytes (the recorder's unknown-type fallback, log tools).
    void SubscribeRaw(const std::string& channel_regex, RawHandler handler);

    // Encodes and publishes; counts failures (LCM returns non-zero when the send fails).
    template <class Msg>
    bool Publish(const std::string& channel, const Msg& msg);
    bool PublishRaw(const std::string& channel, const void* data, int size);

    // Dispatches messages for up to `timeout`; returns true when at least one was handled.
    // Rethrows the first exception a handler raised (after LCM has returned).
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

    std::string url_;
    std::unique_ptr<lcm::LCM> lcm_;
    std::vector<std::unique_ptr<Subscriber>> subscribers_;
    BusCounters counters_;
    SeqTracker seq_;
    std::exception_ptr pending_;
};

template <class Msg>
void Bus::Subscribe(const std::string& channel_regex,
                    std::function<void(const Msg&, const std::string& channel)> handler) {
    AddSubscription(channel_regex, [this, handler = std::move(handler)](
                                       const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
        Msg msg;
        if (!DecodeMessage(msg, rbuf.data, static_cast<int>(rbuf.data_size))) {
            ++counters_.decode_errors;
            counters_.last_decode_error =
                "channel " + channel + ": payload is not a valid " + Msg::getTypeName();
            return;
        }
        ++counters_.received;
        if constexpr (requires { msg.seq; }) NoteSeq(channel, msg.seq);
        handler(msg, channel);
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

}  // namespace gyrocal
