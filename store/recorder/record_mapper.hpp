#pragma once
// RecordMapper: from one received LCM message (channel + bytes) to the store row it becomes.
// LCM-type-aware but socket-free, so it is tested with encoded messages and no bus.
//
// Type by fingerprint: every LCM message starts with its type's 8-byte hash (big-endian). It is
// compared with each known type's getHash(); an unknown hash becomes a raw event (kept whole,
// undecoded); a known hash that then fails to decode counts a decode error on its channel and is
// kept as a raw event too. The channel name is never used to guess a type.
//
// Run in force: the latest run event decides. "start" (and any other event except stop/abort)
// makes its run_id current; "stop"/"abort" is stored with its run, then the current run becomes
// "" (the no-run bucket). Plateaus, sensitivity points, coefficient sets, fit reports and noise
// estimates keep the run_id they carry; everything else gets the run in force.
//
// Loss: sample types with a seq (gyro, encoder, chamber state, rate) feed a SeqTracker per
// channel; gaps and backward steps are returned as loss deltas of the run in force.
//
// Batches (gyro_batch_t, encoder_batch_t, rate_batch_t) become one row per sample, exactly the
// rows their samples would have made alone (seq tracked per sample). Flow marks and acks are
// transport control: handled, not stored.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lcmtypes/bus/seq_tracker.hpp"
#include "store/db/rows.hpp"

namespace gyrocal::recorder {

struct MapperOptions {
    bool store_rates = true;  // false: RATE_* messages are counted but not stored
    static MapperOptions Defaults() { return {}; }
};

struct Mapped {
    std::optional<db::Row> row;  // nothing for skipped messages (rates when off, flow control)
    std::vector<db::Row> more;   // a batch's samples after the first, in order
    bool essential = false;      // run events, coefficient sets, fit reports, noise: never dropped
    std::string run_id;          // run the loss below belongs to
    db::LossDelta loss;          // seq gaps / decode errors this message revealed
    // Flow control (flow_mark_t, flow_ack_t) or an empty batch: handled, nothing to store. The
    // pacing a source did is recorded through its STATUS (flow_* counters).
    bool control = false;
};

class RecordMapper {
public:
    RecordMapper(MapperOptions options, std::string initial_run_id);

    // `recv_utime` [us] is the receive wall clock. Never throws on bad bytes.
    Mapped Map(const std::string& channel, const void* data, int size, int64_t recv_utime);

    const std::string& current_run() const { return run_id_; }
    // Starts a channel's seq tracking at `last_seq` (a restarted recorder: what it missed while
    // down then shows as a gap on the first message).
    void SeedSeq(const std::string& channel, int64_t last_seq) { seq_.Observe(channel, last_seq); }

private:
    template <class Msg, class R>
    void MapDecoded(const Msg& msg, R row, const std::string& channel, int64_t recv_utime,
                    Mapped& out);

    MapperOptions options_;
    std::string run_id_;
    bus::SeqTracker seq_;
};

// The first 8 bytes as LCM writes a type hash (big-endian), or nullopt when size < 8.
std::optional<uint64_t> Fingerprint(const void* data, int size);
std::string FingerprintHex(const void* data, int size);

}  // namespace gyrocal::recorder
