#pragma once
// Internal to gyrocal_analysis: the run's own noise, measured, and noise like it drawn at will.
//
// Measured: the overlapping Allan deviation (noise/allan.hpp) of a model's residual over the
// still bins, per contiguous stretch (a move or a gap starts another; stretches that disagree
// with the rest - a knock, a step - screened out as the noise library does), from the bin length
// to a quarter of the longest stretch (at least 3 bins; each stretch up to half its length), and
// the IEEE 952 terms fitted to it:
//     AVAR(tau) = N^2 / tau + B^2 + K^2 tau / 3      (white, flicker level B, rate random walk K).
// What a perfect model would leave in a bin beyond its white scatter - the slow noise - is then
// the variance of a bin mean of flicker B and random walk K about the run's mean over its span
// (noise::SlowNoiseVariance); k of the floor bound (analyze.hpp, step 9) is its square root over
// the floor. A model error slow enough to look like noise raises B and K and so the bound: a
// missing effect can make the bound more lenient, never stricter (the tests that catch effects
// are the held-out and surrogate tests, not the bound).
// Drawn: noise vectors on the bins' own times (gaps and moves included) with that Allan
// deviation: white N^2 / bin_s per bin; flicker as a bank of Ornstein-Uhlenbeck processes with
// correlation times bin_s 3^j up to 3x the span, of equal variance scaled so that the bank's
// Allan variance at the bins' tau grid matches B^2 (least squares over the grid, the discrete
// process's own Allan variance); a random walk of K^2 per second. These are the surrogates the
// analysis' null distributions are built from (null.hpp): the run's own noise, not an assumed one.
#include <Eigen/Dense>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "processors/analysis/bins.hpp"

namespace gyrocal::analysis::detail {

struct NoiseModel {
    bool measured = false;       // false: not fitted (k assumed 1, flicker_v set to give it)
    double white_v2 = 0.0;       // [V^2] N^2 / bin_s: white variance of one bin mean
    double flicker_v = 0.0;      // [V] B
    double rrw_v_rts = 0.0;      // [V/sqrt(s)] K
    double arw_v_rthz = kNan;    // [V/sqrt(Hz)] N (NaN when not measured)
    double arw_se = kNan;        // [V/sqrt(Hz)] standard error of N (jackknife over stretches)
    double flicker_se_v = kNan;  // [V] standard error of B
    double slow_v2 = 0.0;        // [V^2] slow noise of a bin mean about the run's mean
    double k = 1.0;              // [1] sqrt(slow_v2) / floor (floor bound, step 9)
    std::string note;            // how it was measured, or why not
    // [V^2] AVAR(tau) = N^2 / tau + B^2 + K^2 tau / 3 of the terms above (bin_s: white_v2's)
    double Avar(double bin_s, double tau_s) const;
};

// residual: per bin (bins' order); floor_v: the Allan deviation at the bin length.
NoiseModel MeasureNoise(const std::vector<Bin>& bins, const Eigen::VectorXd& residual, double bin_s,
                        double floor_v);

// The Allan terms alone, as MeasureNoise fits them (the same stretches, screening, taus and fit;
// when they cannot be fitted, the same white and assumed flicker): measured, white_v2, flicker_v
// and rrw_v_rts set, without what only the report and the floor bound use (N and its standard
// errors, the slow noise of a bin mean, k, the note). The windows test refits them on the run and
// on every surrogate (evidence.cpp): 201 fits per analysis, so the cheaper the better.
NoiseModel MeasureAllanTerms(const std::vector<Bin>& bins, const Eigen::VectorXd& residual,
                             double bin_s, double floor_v);

// Draws noise vectors with the model's Allan deviation on the bins' times.
class SurrogateNoise {
public:
    SurrogateNoise(const NoiseModel& model, const std::vector<Bin>& bins, double bin_s);
    Eigen::VectorXd Draw(std::mt19937_64& rng) const;

private:
    std::vector<double> t_s_;  // bins' mid times [s]
    double white_sd_ = 0.0, rrw_ = 0.0;
    std::vector<double> ou_tau_s_;
    double ou_sd_ = 0.0;
};

}  // namespace gyrocal::analysis::detail
