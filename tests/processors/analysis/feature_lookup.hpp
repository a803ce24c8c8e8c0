#pragma once
// Reading an analysis result as the analysis tests ask about it.
#include <string>

#include "processors/analysis/analyze.hpp"

namespace gyrocal::analysis::testing {

// The strongest feature that explains held-out data (the result lists those first, strongest
// first); null when none does.
inline const FeatureResult* FirstExplaining(const SensorResult& r) {
    for (const FeatureResult& f : r.features)
        if (f.explains_heldout) return &f;
    return nullptr;
}

// The result's candidate for `effect`; null when it has none.
inline const CandidateResult* CandidateFor(const SensorResult& r, const std::string& effect) {
    const CandidateResult* found = nullptr;
    for (const CandidateResult& c : r.candidates)
        if (c.effect == effect) found = &c;
    return found;
}

// The last feature named `feature` (e.g. "periodic"); null when there is none.
inline const FeatureResult* LastFeature(const SensorResult& r, const std::string& feature) {
    const FeatureResult* found = nullptr;
    for (const FeatureResult& f : r.features)
        if (f.feature == feature) found = &f;
    return found;
}

}  // namespace gyrocal::analysis::testing
