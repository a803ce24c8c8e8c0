#pragma once
// A method's held-out figures summed over seeds and units (the procedure benchmarks: ramp and
// closed loop). Header-only.
#include <cmath>
#include <string>
#include <vector>

namespace gyrocal::bench {

// A method's held-out figures over seeds and units: rate RMS of the 10 s bin means over every
// unit, drift = RMS over units of the integrated error / duration.
struct Row {
    std::string label;
    double sum2 = 0, sum2_drift = 0;
    long n = 0;
    int units = 0;
    void Add(const std::vector<double>& err_dps, double angle_deg, double duration_s) {
        for (double e : err_dps)
            if (std::isfinite(e)) sum2 += e * e, ++n;
        const double drift_dph = angle_deg / duration_s * 3600.0;
        sum2_drift += drift_dph * drift_dph;
        ++units;
    }
    double Rms() const { return n > 0 ? std::sqrt(sum2 / n) : NAN; }
    double Drift() const { return units > 0 ? std::sqrt(sum2_drift / units) : NAN; }
};

}  // namespace gyrocal::bench
