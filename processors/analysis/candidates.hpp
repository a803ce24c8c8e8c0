#pragma once
// Internal to gyrocal_analysis: the candidate effects and the design matrices on bins.
//   Candidate           one offset effect (a registry term, or a term with a searched parameter)
//   OffsetCandidates    the five offset candidates with why each cannot be tested on this run
//                       (too few ramp bins, no branches, too few temperature bands, supply not
//                       recorded everywhere, no still data soon after power-on)
//   Separation          the measurement that would tell two collinear candidates apart
//   Design / Column     term values per bin (model::TermValues: the same code as the compensator)
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "analyze.hpp"
#include "bins.hpp"

namespace gyrocal::analysis::detail {

std::string Fmt(double v, int prec = 3);

// T0 of the declared model: mid-range rounded to 5 degC, as the fitter does.
double RoundT0(double lo_c, double hi_c);

struct Candidate {
    std::string effect, term, unit;
    bool search_tau = false;
    std::string why_not;  // "" = testable
};

Eigen::MatrixXd Design(const std::vector<std::string>& terms, double t0_c,
                       const std::vector<Bin>& bins, int64_t first_utime);
Eigen::VectorXd Column(const std::string& term, double t0_c, const std::vector<Bin>& bins,
                       int64_t first_utime);

std::string WarmupTerm(double tau_s);

std::string Separation(const std::string& a, const std::string& b);

std::vector<Candidate> OffsetCandidates(const SensorRun& run, const std::vector<Bin>& bins,
                                        const AnalysisOptions& o);

}  // namespace gyrocal::analysis::detail
