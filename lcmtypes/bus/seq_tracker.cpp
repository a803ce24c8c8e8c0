#include "lcmtypes/bus/seq_tracker.hpp"

#include <limits>

namespace gyrocal::bus {

namespace {

constexpr int64_t kMax = std::numeric_limits<int64_t>::max();

// Samples missing between `last` and `seq` (> last): seq - last - 1, computed without signed
// overflow for any pair (a hostile or corrupt seq may be near INT64_MIN or INT64_MAX; found by
// the fuzz harness recorder_map), saturating at INT64_MAX.
int64_t Gap(int64_t last, int64_t seq) {
    const uint64_t step = static_cast<uint64_t>(seq) - static_cast<uint64_t>(last);
    return step - 1 > static_cast<uint64_t>(kMax) ? kMax : static_cast<int64_t>(step - 1);
}

int64_t SaturatingAdd(int64_t a, int64_t b) { return a > kMax - b ? kMax : a + b; }  // a, b >= 0

}  // namespace

SeqReport SeqTracker::Observe(const std::string& stream, int64_t seq) {
    SeqReport r;
    auto it = last_seq_.find(stream);
    if (it == last_seq_.end()) {
        last_seq_.emplace(stream, seq);
        missing_.emplace(stream, 0);
        return r;
    }
    if (seq > it->second) {
        r.missing = Gap(it->second, seq);
    } else {
        r.backwards = true;
        ++total_backwards_;
    }
    it->second = seq;
    missing_[stream] = SaturatingAdd(missing_[stream], r.missing);
    total_missing_ = SaturatingAdd(total_missing_, r.missing);
    return r;
}

int64_t SeqTracker::missing_of(const std::string& stream) const {
    auto it = missing_.find(stream);
    return it == missing_.end() ? 0 : it->second;
}

}  // namespace gyrocal::bus
