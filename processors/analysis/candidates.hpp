#pragma once
// Internal to gyrocal_analysis: the candidate effects and the regressors they put on bins.
//   Candidate           one offset effect: a registry term, or a family of terms with a shape
//                       parameter searched on a grid (dT/dt time constant, branch width, warm-up
//                       time constant, spline knot); why it cannot be tested on this run
//   OffsetCandidates    the candidates with their grids and testability
//   Separation          the measurement that would tell two collinear candidates apart
//   Context             the training rows the choice is made on
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"

namespace gyrocal::analysis::detail {

// T0 of the declared model: mid-range rounded to 5 degC, as the fitter does.
double RoundT0(double lo_c, double hi_c);

struct Candidate {
    std::string effect, unit;
    std::vector<std::string> grid;  // the term, or the term at each searched parameter value
    std::string why_not;            // "" = testable
    // Considered only when no other candidate passes at a forward step, and kept out of the
    // noise model of the others' tests: a generic shape that must not take the place of a
    // listed effect the profile makes look alike (a branch on a one-way profile is a static
    // function of the temperature too).
    // ... until this effect is in the model; from then on it competes like any candidate.
    bool last_resort = false;
    std::string competes_after;
    // A term on the rate tracker (thermometer_lag's dT x dT/dt): a coefficient set tracks dT/dt
    // with one time constant, so once the model has a term on that tracker (dTdt or dT*dTdt,
    // declared or added) it is tested only at that term's time constant; until then on `grid`
    // (temp_rate's time constants). temp_rate is tied the same way to a dT*dTdt in the model.
    bool on_rate_tracker = false;
};

std::string Separation(const std::string& a, const std::string& b);

std::vector<Candidate> OffsetCandidates(const BinnedRun& binned, const AnalysisOptions& o);

// The rows (bins) a fit is made on, with their segments recomputed so that a row whose
// predecessor bin is not among the rows starts a new segment.
// Nuisance columns (the joint search, analyze.hpp step 8: a strong time-shaped generic feature
// accounted for while the candidates are tested) follow the terms' columns in every design: they
// are fitted with the terms and never become a term (nothing downstream can evaluate them).
struct Context {
    const BinnedRun* binned = nullptr;
    std::vector<Eigen::Index> rows;
    double t0 = 25.0;
    Eigen::VectorXd y;
    std::vector<int> segment;
    int hac_lag = 0, cv_guard = 0, cv_blocks = 10;
    Eigen::MatrixXd nuisance_all;  // on all bins (0 columns: none)
    Eigen::VectorXd Column(const std::string& term) const;
    // The terms' columns, then the nuisance columns, on the rows / on all bins.
    Eigen::MatrixXd Design(const std::vector<std::string>& terms) const;
    Eigen::MatrixXd AllDesign(const std::vector<std::string>& terms) const;
};
Context MakeContext(const BinnedRun& binned, std::vector<Eigen::Index> rows, double t0,
                    const AnalysisOptions& o, const Eigen::MatrixXd& nuisance_all = {});

}  // namespace gyrocal::analysis::detail
