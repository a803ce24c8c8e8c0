#pragma once
// The Allan deviation of ONE unit from the still stretches of its own run (allan.hpp for the
// math), fed sample by sample by the process that sees every sample and knows table motion.
//
// Stretches: consecutive samples with the table at rest (moving false), no sequence gap and a
// regular interval (within 50 % of the stretch's first interval); anything else closes the
// stretch. Samples are averaged into bins of bin_s (an integer number of samples).
// Thermally quiet segments: a temperature ramp moves the offset through the unit's temperature
// coefficient (up to ~1 mV/K, 0.17 deg/s per K), which is no noise. A closed stretch is cut into
// the runs of bins where the temperature's slope (a line over slope_window_s centred on the bin)
// stays within quiet_slope_c_per_min; runs shorter than min_segment_s are dropped. What is left
// of the offset's temperature dependence inside a segment (the settling tail moves the
// temperature by a few tenths of a degree) is taken out by regressing the bin values on the
// segment's smoothed temperature (a line), before the Allan sums are formed. Segments whose Allan
// variance is far above the others' (a disturbance inside them) are left out (allan.hpp:
// ScreenSegments, alpha 0.01) and the estimate's note says so.
// A stretch longer than 4 max_tau_s (8000 s by default: a ramp or a dwell without a turn) is
// closed as a segment every 4 max_tau_s and goes on as the next: a segment that long already
// reaches every tau of the grid (allan.hpp: a segment adds taus up to a quarter of its length),
// and keeping all of it would grow with the rest (0.86 MB per unit-hour at 0.1 s bins). So the
// stretch under way holds at most 4 max_tau_s / bin_s bins (1.9 MB per unit by default).
// Quiet threshold 0.1 degC/min: twice the plateau criterion's slope limit, so the settling tails
// before each plateau count (5-15 minutes per setpoint instead of the plateau's 1-2); the sensor
// lag of a 15 s temperature line then misstates the die by at most 0.025 degC, which the
// regression turns into < 0.03 mV of slowly varying error.
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "processors/motion/gyro_sample.hpp"
#include "processors/noise/allan.hpp"

namespace gyrocal::noise {

struct TrackerConfig {
    double bin_s = 0.1;                  // [s] tau0 (at least one sample interval)
    double quiet_slope_c_per_min = 0.1;  // [degC/min] thermally quiet
    double slope_window_s = 60.0;        // [s] line fit for the slope
    double min_segment_s = 60.0;         // [s] shorter quiet runs are not used
    double min_fit_tau_s = 0.5;          // [s] shortest tau in the terms' fit (above the low-pass)
    double max_tau_s = 2000.0;           // [s] grid limit
    static TrackerConfig Defaults() { return {}; }
    std::string Validate() const;  // "" when valid
};

struct NoiseEstimate {
    int64_t utime = 0;   // [us] newest sample included
    double still_s = 0;  // [s] in the quiet segments used
    int segments = 0;
    double longest_s = 0;  // [s] longest segment
    double tau0_s = 0;     // [s] bin length
    std::vector<AllanPoint> adev;
    NoiseTerms terms;
};

class NoiseTracker {
public:
    explicit NoiseTracker(const TrackerConfig& config);  // throws invalid_argument if invalid
    // One gyro sample, utime increasing (the caller guards order and finiteness); moving: the table
    // moved within the guard interval (the sample closes the still stretch).
    void Add(const motion::GyroSample& s, bool moving);
    // Forgets everything (a new run).
    void Reset();
    // The estimate over the closed segments and the still stretch under way.
    NoiseEstimate Estimate() const;
    int64_t newest_utime() const { return newest_utime_; }
    // Bins of the stretch under way (at most 4 max_tau_s / bin_s).
    size_t held_bins() const { return bins_.size(); }

private:
    struct Bin {
        double t_s, value, temp_c;
    };
    void CloseStretch();
    // Quiet segments of `bins` -> Allan sums appended to `out`.
    void Segment(const std::vector<Bin>& bins, std::vector<SegmentSums>& out) const;

    TrackerConfig config_;
    std::vector<int64_t> grid_;
    std::vector<SegmentSums> closed_;
    // The stretch under way.
    std::vector<Bin> bins_;
    int64_t last_utime_ = 0, last_seq_ = 0, interval_us_ = 0;
    bool in_stretch_ = false;
    int per_bin_ = 0;
    double bin_sum_ = 0, bin_temp_ = 0, bin_t_ = 0;
    int bin_n_ = 0;
    double tau0_s_ = 0;
    size_t max_held_bins_ = 0;  // 4 max_tau_s / tau0: the stretch under way is closed there
    int64_t newest_utime_ = 0;
};

}  // namespace gyrocal::noise
