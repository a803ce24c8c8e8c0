#pragma once
// The parts of `gyrocal show RUN` about the fitter's conclusions (schema v5): each final set
// complete or partial and why, points excluded, the slow noise used and its source, repeatability
// at revisited temperatures, and each unit's Allan deviation figures.
#include <nlohmann/json.hpp>
#include <string>

#include "store/db/query.hpp"

namespace gyrocal::store::format {

// " COMPLETE", " PARTIAL: why", or "" when no report names this set.
std::string SetStatusLabel(const RunDetail& d, const CoeffSetInfo& c);
// "Fit reports", "Repeatability" and "Noise" sections (each says "none recorded" when empty).
std::string FitSectionsText(const RunDetail& d);
// The same as "fit_reports" and "noise" members of `j`.
void AddFitJson(nlohmann::json& j, const RunDetail& d);

}  // namespace gyrocal::store::format
