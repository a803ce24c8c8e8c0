#pragma once
// Turntable motion from the optical encoder, shared by the plateau detector (which must neither
// average nor judge stability on samples taken while the table turns), the rotation estimator
// (which integrates over each move) and the analysis (which fits only still data).
//
// Move detection (MoveDetector): at rest the encoder count may dither by a count or so at a line
// edge, so "moving" needs a threshold. The table LEAVES rest when |counts - rest_counts| exceeds
// start_threshold_counts; the move's start time is that of the last reading still at rest (the
// true start lies between the two readings). While moving, every change larger than
// settle_band_counts from the current settle reference restarts the settle clock; once the
// counts have stayed within the band for settle_s of encoder time the move is OVER, with
// end_utime = time of the last change beyond the band and end_counts = the reading that ended
// it (the table's last counts arrive one by one, inside the band). The encoder must publish
// continuously (also at rest): time only advances with its readings.
//
// Sample classification (TableMotion): a sample at time t is "moving" when t lies within guard_s
// of a move, i.e. in [start - guard, end + guard], or after start - guard of a move still under
// way. That decision needs encoder data up to t + guard, so it is only final once the encoder's
// newest reading is that late; when the encoder is silent (no encoder at all, e.g. CSV data, or a
// dead link) a sample is decided anyway once its own stream is stale_s past it, with what is known.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace gyrocal::motion {

// One encoder reading, live (the nodes, from ENCODER) or recorded (the analysis' runs, the fitter's
// ramp mode); the analysis drops and counts readings without counts_per_rev.
struct EncoderReading {
    int64_t utime = 0;           // [us] producer clock
    int64_t counts = 0;          // [count] cumulative, signed
    int32_t counts_per_rev = 0;  // [count/rev] > 0 in a usable reading
};

struct TableMove {
    int64_t start_utime = 0;   // [us] last reading at rest before the table left
    int64_t end_utime = 0;     // [us] last reading that changed (the table stopped here)
    int64_t start_counts = 0;  // [count] rest position before
    int64_t end_counts = 0;    // [count] rest position after
    int32_t counts_per_rev = 0;
    double count_deg() const { return 360.0 / counts_per_rev; }  // [deg] one count
    double angle_deg() const {
        return static_cast<double>(end_counts - start_counts) * count_deg();
    }
    // True when t_utime lies within guard_us of this move, [start - guard, end + guard]: a sample
    // there is moving (live in TableMotion, offline in the analysis).
    bool Near(int64_t t_utime, int64_t guard_us) const {
        return t_utime >= start_utime - guard_us && t_utime <= end_utime + guard_us;
    }
};

struct MoveDetectorConfig {
    int64_t start_threshold_counts = 2;  // [count] leaving rest: > this from the rest position
    int64_t settle_band_counts = 1;      // [count] dither tolerated while settling
    double settle_s = 0.5;               // [s] within the band this long = at rest again
    static MoveDetectorConfig Defaults() { return {}; }
    // "" when valid, else a sentence naming the field and its valid range.
    std::string Validate() const;
};

class MoveDetector {
public:
    explicit MoveDetector(const MoveDetectorConfig& config);

    // Feeds one reading; utime must increase (the caller guards). Returns the move this reading
    // completed, if any. A change of counts_per_rev restarts detection at rest.
    std::optional<TableMove> Feed(const EncoderReading& reading);

    bool moving() const { return moving_; }
    // [us] start of the move under way; nullopt at rest.
    std::optional<int64_t> current_start_utime() const;
    // The move under way taken to last until last_utime (the readings ended mid-move: it lasts to
    // the last reading); nullopt at rest. Only its times are known.
    std::optional<TableMove> MoveUnderWay(int64_t last_utime) const;
    // [us] newest reading; nullopt before any.
    std::optional<int64_t> watermark_utime() const;

private:
    MoveDetectorConfig config_;
    bool have_ = false;
    bool moving_ = false;
    EncoderReading last_{};
    int64_t rest_counts_ = 0;
    TableMove current_{};
    int64_t settle_ref_counts_ = 0;
    int64_t last_change_utime_ = 0;
};

// The default guard_s [s] of TableMotion: one value for everything that classifies samples as
// still or moving the way gyrocal-plateau does (its --motion-guard-s, the in-process virtual lab,
// the analysis' BuildOptions), so that what the live detector averages and what is fitted later
// are the same samples.
inline constexpr double kDefaultGuardS = 1.0;

class TableMotion {
public:
    TableMotion(const MoveDetectorConfig& config, double guard_s, double stale_s);

    std::optional<TableMove> Feed(const EncoderReading& reading);

    // True when a sample at t_utime can be classified now; newest_stream_utime is the newest
    // sample time of the sample's own stream.
    bool Decided(int64_t t_utime, int64_t newest_stream_utime) const;
    // True when the table moved within guard_s of t_utime (see the header comment).
    bool Moving(int64_t t_utime) const;
    // Forgets moves that ended before t_utime - guard (nothing older will be asked).
    void Prune(int64_t t_utime);

    const MoveDetector& detector() const { return detector_; }

private:
    MoveDetector detector_;
    int64_t guard_us_;
    int64_t stale_us_;
    std::deque<TableMove> moves_;
};

}  // namespace gyrocal::motion
