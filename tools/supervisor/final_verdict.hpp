#pragma once
// What `gyrocal calibrate` says at the end of a run about each unit's final coefficient set: the
// fitter's FIT_<id> report made by the run's stop says complete, partial (and why) or none. A set
// that arrived before the stop and no final one since is not final either. Exit 3 unless every
// unit is complete; the table marks each set that is not.
#include <map>
#include <set>
#include <string>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"

namespace gyrocal::supervisor {

struct FinalVerdict {
    std::set<std::string> sensors;                     // the run's units
    const std::map<std::string, coeff_set_t>& newest;  // newest set of each unit
    const std::set<std::string>& final_sets;           // units with a set after the stop
    const std::map<std::string, fit_report_t>& final_reports;

    bool AllComplete() const;
    // Per unit with a set: "" when complete and final, else a label for the table
    // ("PARTIAL: why", "NOT FINAL: ...").
    std::map<std::string, std::string> Labels() const;
    // One paragraph per unit that is not complete: which unit, why, what was published.
    std::string Explain() const;
};

}  // namespace gyrocal::supervisor
