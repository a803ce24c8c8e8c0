#include "seq_tracker.hpp"

namespace gyrocal {

SeqReport SeqTracker::Observe(const std::string& stream, int64_t seq) {
    SeqReport r;
    auto it = last_seq_.find(stream);
    if (it == last_seq_.end()) {
        last_seq_.emplace(stream, seq);
        missing_.emplace(stream, 0);
        return r;
    }
    const int64_t expected = it->second + 1;
    if (seq >= expected) {
        r.missing = seq - expected;
    } else {
        r.backwards = true;
        ++total_backwards_;
    }
    it->second = seq;
    missing_[stream] += r.missing;
    total_missing_ += r.missing;
    return r;
}

int64_t SeqTracker::missing_of(const std::string& stream) const {
    auto it = missing_.find(stream);
    return it == missing_.end() ? 0 : it->second;
}

}  // namespace gyrocal
