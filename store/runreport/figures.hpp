#pragma once
// The figures of a unit (plot/figure.hpp, drawn by gnuplot like every figure of the project):
//   <stem>_offset      offset [V] vs temperature: the plateau means with error bars (standard error
//                      combined with the run's plateau slow noise: what the fitter weighted them
//                      by), the fitted curve and its band of +-2 sigma from the coefficient
//                      covariance (model::Evaluator's variance phi' C phi);
//   <stem>_sens        sensitivity [mV/(deg/s)] vs temperature: accepted turns (+90 and -90) with
//                      their standard errors, refused turns apart, the fitted curve and its band;
//   <stem>_resid_temp  offset residual [mV] (plateau mean - fitted curve) vs temperature, with the
//                      band around zero: a point outside the band by more than its error bar is a
//                      point the model does not explain;
//   <stem>_resid_time  the same residuals vs time since the run started [h] (TimeOrigin);
//   <stem>_sens_resid  sensitivity residual [%] of each accepted turn vs temperature, with the
//   band.
// A figure without data is left out (the section says why); a series without a finite value is
// dropped (gnuplot refuses a plot with no valid point at all). Pure.
#include <cstdint>
#include <string>
#include <vector>

#include "processors/plot/figure.hpp"
#include "store/runreport/unit_data.hpp"

namespace gyrocal::runreport {

// Band half-width in standard deviations of the fitted curve.
inline constexpr double kBandSigmas = 2.0;

// [us] the origin of the time axes: the run's start (message time) when it precedes the
// earliest plateau or turn window by less than a week, else that window's start.
int64_t TimeOrigin(const db::RunDetail& detail);

// `stem`: a plain file stem unique in the report (e.g. "u1"); the sensor id goes in the titles.
std::vector<plot::Figure> UnitFigures(const UnitData& unit, const std::string& stem,
                                      double plateau_slow_noise_dps, int64_t time_origin_utime);

}  // namespace gyrocal::runreport
