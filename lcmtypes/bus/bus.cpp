#include "bus.hpp"

#include <cstdlib>

namespace gyrocal {

std::string BusOptions::ResolvedUrl() const {
    if (!url.empty()) return url;
    if (const char* env = std::getenv("GYROCAL_LCM_URL"); env && *env) return env;
    return kDefaultLcmUrl;
}

Bus::Bus(const BusOptions& options) : url_(options.ResolvedUrl()) {
    lcm_ = std::make_unique<lcm::LCM>(url_);
    if (!lcm_->good()) {
        throw BusError(
            "cannot open LCM at '" + url_ +
            "': for udpm, this host needs a multicast route. Fix (as root): "
            "ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo "
            "- or set GYROCAL_LCM_URL / --lcm-url to a provider that works here");
    }
}

Bus::~Bus() {
    // Unsubscribe before the Subscriber objects die so LCM never calls into freed memory.
    lcm_.reset();
}

void Bus::Subscriber::OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    if (bus->pending_) return;  // a failed handler stops dispatch until Handle() rethrows
    try {
        fn(*rbuf, channel);
    } catch (...) {
        bus->pending_ = std::current_exception();
    }
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
    return true;
}

bool Bus::Handle(std::chrono::milliseconds timeout) {
    const int n = lcm_->handleTimeout(static_cast<int>(timeout.count()));
    if (pending_) {
        std::exception_ptr e = pending_;
        pending_ = nullptr;
        std::rethrow_exception(e);
    }
    if (n < 0) throw BusError("LCM handle failed on '" + url_ + "'");
    return n > 0;
}

void Bus::NoteSeq(const std::string& channel, int64_t seq) {
    const SeqReport r = seq_.Observe(channel, seq);
    counters_.seq_gaps += r.missing;
    counters_.seq_backwards += r.backwards ? 1 : 0;
}

}  // namespace gyrocal
