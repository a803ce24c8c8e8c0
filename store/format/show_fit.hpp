#pragma once
// The parts of `gyrocal show RUN` about the fitter's conclusions (schema v5): each final set
// complete or partial and why, points excluded, the slow noise used and its source, repeatability
// at revisited temperatures, and each unit's Allan deviation figures.
#include <nlohmann/json.hpp>
#include <string>

#include "store/db/query.hpp"

namespace gyrocal::format {

// " COMPLETE", " PARTIAL: why", or "" when no report names this set.
std::string SetStatusLabel(const db::RunDetail& d, const db::CoeffSetInfo& c);
// "Fit reports", "Repeatability" and "Noise" sections (each says "none recorded" when empty).
std::string FitSectionsText(const db::RunDetail& d);
// The same as "fit_reports" and "noise" members of `j`.
void AddFitJson(nlohmann::json& j, const db::RunDetail& d);

}  // namespace gyrocal::format
