#include "lcmtypes/bus/sample_batcher.hpp"

namespace gyrocal::bus {

void SampleBatcher::Add(const std::string& channel, const gyro_sample_t& m) {
    if (max_ <= 1) {
        bus_.Publish(channel, m);
        return;
    }
    Gyros* g = nullptr;
    for (Gyros& x : gyros_)
        if (x.channel == channel) g = &x;
    if (!g) g = &gyros_.emplace_back(Gyros{channel, {}});
    g->samples.push_back(m);
    ++held_;
    if (static_cast<int>(g->samples.size()) >= max_) full_ = true;
}

void SampleBatcher::AddEncoder(const std::string& channel, const encoder_sample_t& m) {
    if (max_ <= 1) {
        bus_.Publish(channel, m);
        return;
    }
    encoder_channel_ = channel;
    encoders_.push_back(m);
    ++held_;
    if (static_cast<int>(encoders_.size()) >= max_) full_ = true;
}

bool SampleBatcher::Flush() {
    bool ok = true;
    if (!encoders_.empty()) {
        ok = bus_.PublishSamples(encoder_channel_, std::move(encoders_)) && ok;
        encoders_.clear();
    }
    for (Gyros& g : gyros_) {
        if (g.samples.empty()) continue;
        ok = bus_.PublishSamples(g.channel, std::move(g.samples)) && ok;
        g.samples.clear();
    }
    held_ = 0;
    full_ = false;
    return ok;
}

}  // namespace gyrocal::bus
