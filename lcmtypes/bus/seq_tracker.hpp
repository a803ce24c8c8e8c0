#pragma once
// Sequence-gap accounting per publisher stream. Each producer numbers its samples seq = 0,1,2...
// on each stream (channel); UDP multicast can lose packets, so a jump forward of k means k-1
// samples were lost on the way. A step backwards is either a reordered packet or a restarted
// producer; both are counted and tracking resynchronises on the new value.
#include <cstdint>
#include <map>
#include <string>

namespace gyrocal::bus {

struct SeqReport {
    int64_t missing = 0;     // samples skipped by this step (0 when in order)
    bool backwards = false;  // seq did not increase (reorder, duplicate or producer restart)
};

class SeqTracker {
public:
    // Feeds one received seq of a stream; returns what this step says about loss.
    SeqReport Observe(const std::string& stream, int64_t seq);

    int64_t total_missing() const { return total_missing_; }
    int64_t total_backwards() const { return total_backwards_; }
    int64_t missing_of(const std::string& stream) const;
    const std::map<std::string, int64_t>& missing_by_stream() const { return missing_; }

private:
    std::map<std::string, int64_t> last_seq_;
    std::map<std::string, int64_t> missing_;
    int64_t total_missing_ = 0;
    int64_t total_backwards_ = 0;
};

}  // namespace gyrocal::bus
