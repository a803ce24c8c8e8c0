#include "lcmtypes/bus/bus.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace gyrocal::bus {

std::string BusOptions::ResolvedUrl() const {
    if (!url.empty()) return url;
    if (const char* env = std::getenv("GYROCAL_LCM_URL"); env && *env) return env;
    return kDefaultLcmUrl;
}

std::optional<UdpmAddress> ParseUdpm(const std::string& url) {
    const std::string scheme = "udpm://";
    if (url.rfind(scheme, 0) != 0) return std::nullopt;
    const std::string rest = url.substr(scheme.size());
    const size_t q = rest.find('?');
    const std::string hostport = rest.substr(0, q);
    UdpmAddress a;
    a.options = q == std::string::npos ? "" : rest.substr(q + 1);
    const size_t colon = hostport.find(':');
    a.group = hostport.substr(0, colon);
    in_addr probe{};
    if (a.group.empty() || inet_pton(AF_INET, a.group.c_str(), &probe) != 1) return std::nullopt;
    if (colon != std::string::npos) {
        const std::string port = hostport.substr(colon + 1);
        if (port.empty() || port.size() > 5 ||
            port.find_first_not_of("0123456789") != std::string::npos)
            return std::nullopt;
        a.port = std::stoi(port);
        if (a.port < 1 || a.port > 65535) return std::nullopt;
    }
    return a;
}

std::string FormatUdpm(const UdpmAddress& a) {
    return "udpm://" + a.group + ":" + std::to_string(a.port) +
           (a.options.empty() ? "" : "?" + a.options);
}

namespace {

const char* kRouteFix =
    "Fix (as root, LCM's loopback fix): ip link set lo multicast on && "
    "ip route add 224.0.0.0/4 dev lo - or give another provider with --lcm-url / GYROCAL_LCM_URL";

// LCM 1.3.1 opens udpm even where the group is unroutable and only fails on first send, so ask
// the kernel for a route up front: connect() on a UDP socket does exactly that look-up.
void CheckMulticastRoute(const std::string& url) {
    const std::string scheme = "udpm://";
    if (url.rfind(scheme, 0) != 0) return;
    const std::string rest = url.substr(scheme.size());
    const std::string host = rest.substr(0, rest.find_first_of(":?"));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(7667);
    if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1)
        throw BusError("LCM URL '" + url + "': '" + host + "' is not an IPv4 multicast address");
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) throw BusError(std::string("cannot create a UDP socket: ") + std::strerror(errno));
    const int rc = connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    const int err = errno;
    close(fd);
    if (rc != 0) {
        throw BusError("no route to multicast group " + host + " for LCM URL '" + url + "' (" +
                       std::strerror(err) + "). " + kRouteFix);
    }
}

}  // namespace

Bus::Bus(const BusOptions& options) : url_(options.ResolvedUrl()) {
    CheckMulticastRoute(url_);
    lcm_ = std::make_unique<lcm::LCM>(url_);
    if (!lcm_->good()) {
        throw BusError("cannot open LCM at '" + url_ + "'. " + kRouteFix);
    }
}

Bus::~Bus() {
    // Unsubscribe before the Subscriber objects die so LCM never calls into freed memory.
    lcm_.reset();
}

void Bus::Subscriber::OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    // A failed handler does not keep the message from the other subscribers (LCM calls each of
    // them in turn): it is counted, and the first failure is rethrown by Handle().
    std::string what;
    std::exception_ptr failure;
    try {
        fn(*rbuf, channel);
        return;
    } catch (const std::exception& e) {
        what = e.what();
        failure = std::current_exception();
    } catch (...) {
        what = "an exception that is not a std::exception";
        failure = std::current_exception();
    }
    BusCounters& c = bus->counters_;
    ++c.handler_errors;
    ++c.handler_errors_by_channel[channel];
    if (c.first_handler_error.empty()) c.first_handler_error = "channel " + channel + ": " + what;
    if (!bus->pending_) bus->pending_ = failure;
}

void Bus::AddSubscription(const std::string& channel_regex, RawHandler fn) {
    subscribers_.push_back(std::make_unique<Subscriber>(Subscriber{this, std::move(fn)}));
    lcm::Subscription* sub =
        lcm_->subscribe(channel_regex, &Subscriber::OnMessage, subscribers_.back().get());
    if (sub == nullptr) throw BusError("cannot subscribe to '" + channel_regex + "'");
    // 0 = unbounded: LCM's default of 30 drops silently under any burst.
    sub->setQueueCapacity(0);
}

void Bus::SubscribeRaw(const std::string& channel_regex, RawHandler handler) {
    AddSubscription(channel_regex, [this, handler = std::move(handler)](
                                       const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
        ++counters_.received;
        handler(rbuf, channel);
    });
}

bool Bus::PublishRaw(const std::string& channel, const void* data, int size) {
    if (lcm_->publish(channel, data, static_cast<unsigned int>(size)) != 0) {
        ++counters_.publish_errors;
        return false;
    }
    ++counters_.published;
    counters_.published_bytes += size + static_cast<int64_t>(channel.size());
    return true;
}

bool Bus::Handle(std::chrono::milliseconds timeout) {
    const int n = lcm_->handleTimeout(static_cast<int>(timeout.count()));
    if (pending_) {
        std::exception_ptr e = pending_;
        pending_ = nullptr;
        std::rethrow_exception(e);
    }
    if (n < 0) {
        if (errno == EINTR) return false;  // a signal (e.g. SIGTERM) woke select(): not a failure
        throw BusError("LCM handle failed on '" + url_ + "': " + std::strerror(errno));
    }
    return n > 0;
}

void Bus::NoteSeq(const std::string& channel, int64_t seq) {
    const SeqReport r = seq_.Observe(channel, seq);
    counters_.seq_gaps += r.missing;
    counters_.seq_backwards += r.backwards ? 1 : 0;
}

int64_t WallClockUtime() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace gyrocal::bus
