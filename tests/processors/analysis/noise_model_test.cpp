// The run's own noise measured from the residual's still stretches (noise_model.hpp) does not
// depend on the bin length: the same noise binned at 10 s and merged to 40 s (as the ramp fitter
// merges its bins on a day-long run) gives the same N and B, on stretches 290 s long between turns
// (7 bins of 40 s each: shorter than the 8 bins one stretch needed before, which left 40 s bins
// with slow noise assumed and white-only surrogates, and so windows "far from the floor" that the
// 10 s analysis of the same run called adequate).
#include "processors/analysis/noise_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/analysis/bins.hpp"
#include "processors/noise/allan.hpp"

namespace gyrocal::analysis::detail {
namespace {

constexpr double kUs = 1e6;
constexpr double kArwTrue = 3e-4;      // [V/sqrt(Hz)] N, near the rig's
constexpr double kFlickerTrue = 5e-5;  // [V] B, near the rig's

// 300 still stretches of 29 bins of 10 s, 20 s apart (a turn between them).
std::vector<Bin> TenSecondBins() {
    std::vector<Bin> bins;
    double t_s = 0.0;
    for (int s = 0; s < 300; ++s, t_s += 20.0)
        for (int k = 0; k < 29; ++k, t_s += 10.0) {
            Bin b;
            b.mid_utime = (t_s + 5.0) * kUs;
            b.n = 1000;
            b.segment = s;
            bins.push_back(b);
        }
    return bins;
}

// Each stretch's bins merged 4 by 4 (the 29th dropped): 40 s bins, values the means.
void Merge(const std::vector<Bin>& bins, const Eigen::VectorXd& v, std::vector<Bin>* out_bins,
           std::vector<double>* out_v) {
    for (size_t i = 0; i + 3 < bins.size(); ++i) {
        if (bins[i + 3].segment != bins[i].segment) continue;
        const bool starts = i == 0 || bins[i - 1].segment != bins[i].segment ||
                            (out_bins->size() > 0 && out_bins->back().segment == bins[i].segment &&
                             bins[i].mid_utime > out_bins->back().mid_utime + 15.0 * kUs);
        if (!starts) continue;
        Bin b = bins[i];
        b.mid_utime = 0.5 * (bins[i].mid_utime + bins[i + 3].mid_utime);
        b.n = 4 * bins[i].n;
        out_bins->push_back(b);
        out_v->push_back(0.25 * v.segment(static_cast<Eigen::Index>(i), 4).sum());
        i += 3;
    }
}

TEST(NoiseModel, MergedBinsMeasureTheNoiseTheTenSecondBinsMeasure) {
    const std::vector<Bin> bins10 = TenSecondBins();
    NoiseModel truth;
    truth.white_v2 = kArwTrue * kArwTrue / 10.0;
    truth.flicker_v = kFlickerTrue;
    const SurrogateNoise draw(truth, bins10, 10.0);
    std::mt19937_64 rng(7);
    const Eigen::VectorXd r10 = draw.Draw(rng);
    std::vector<Bin> bins40;
    std::vector<double> v40;
    Merge(bins10, r10, &bins40, &v40);
    ASSERT_EQ(bins40.size(), 300u * 7u);
    const Eigen::VectorXd r40 = Eigen::Map<const Eigen::VectorXd>(v40.data(), v40.size());

    const NoiseModel m10 = MeasureNoise(bins10, r10, 10.0, NoiseFloor(bins10, r10).offset_rms_v);
    const NoiseModel m40 = MeasureNoise(bins40, r40, 40.0, NoiseFloor(bins40, r40).offset_rms_v);
    ASSERT_TRUE(m10.measured) << m10.note;
    ASSERT_TRUE(m40.measured) << m40.note;
    // The two estimates come from the same noise, so their difference varies less than the sum of
    // their jackknife variances (over the 300 stretches): 4 of those combined standard errors.
    const double arw10 = m10.arw_v_rthz, arw40 = m40.arw_v_rthz;
    EXPECT_NEAR(arw40, arw10, 4.0 * std::hypot(m10.arw_se, m40.arw_se)) << m40.note;
    EXPECT_NEAR(m40.flicker_v, m10.flicker_v, 4.0 * std::hypot(m10.flicker_se_v, m40.flicker_se_v))
        << m10.note << "\n"
        << m40.note;
    // And the truth: N exactly what was drawn (white), within 4 of each standard error.
    EXPECT_NEAR(arw10, kArwTrue, 4.0 * m10.arw_se);
    EXPECT_NEAR(arw40, kArwTrue, 4.0 * m40.arw_se);
    // B: the surrogates' flicker is a bank of OU processes matched to B over the whole span, so
    // its Allan deviation over 10-120 s is B within the bank's ripple (about 20 %) and the errors.
    for (const NoiseModel* m : {&m10, &m40})
        EXPECT_NEAR(m->flicker_v, kFlickerTrue, 0.2 * kFlickerTrue + 4.0 * m->flicker_se_v)
            << m->note;
    // The slow noise k of the floor bound follows: each bin length's own.
    EXPECT_GT(m40.k, 0.0);
}

// Too little to fit the terms: k = 1 assumed, and the surrogates carry that slow noise (a flicker
// level whose window variance is the floor's), not white noise alone.
TEST(NoiseModel, UnmeasuredNoiseCarriesTheAssumedSlowNoise) {
    std::vector<Bin> bins;
    for (int k = 0; k < 30; ++k) {
        Bin b;
        b.mid_utime = (10.0 * k + 5.0) * kUs;
        b.n = 1000;
        b.segment = k / 3;  // stretches of 3 bins: none long enough
        bins.push_back(b);
    }
    std::mt19937_64 rng(3);
    std::normal_distribution<double> n(0.0, 1e-4);
    Eigen::VectorXd r(static_cast<Eigen::Index>(bins.size()));
    for (Eigen::Index i = 0; i < r.size(); ++i) r[i] = n(rng);
    const double floor_v = 1e-4;
    const NoiseModel m = MeasureNoise(bins, r, 10.0, floor_v);
    EXPECT_FALSE(m.measured);
    EXPECT_DOUBLE_EQ(m.k, 1.0);
    EXPECT_NE(m.note.find("k = 1"), std::string::npos) << m.note;
    EXPECT_NEAR(m.slow_v2, floor_v * floor_v, 1e-12 * floor_v * floor_v);
    ASSERT_GT(m.flicker_v, 0.0);
    EXPECT_NEAR(noise::SlowNoiseVariance(m.flicker_v, 0.0, 10.0, 290.0), floor_v * floor_v,
                1e-9 * floor_v * floor_v);
}

}  // namespace
}  // namespace gyrocal::analysis::detail
