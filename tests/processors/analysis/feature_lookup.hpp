#pragma once
// Reading an analysis result as the analysis tests ask about it.
#include "analysis/analyze.hpp"

namespace gyrocal::analysis::testing {

// The strongest feature that explains held-out data (the result lists those first, strongest
// first); null when none does.
inline const FeatureResult* FirstExplaining(const SensorResult& r) {
    for (const FeatureResult& f : r.features)
        if (f.explains_heldout) return &f;
    return nullptr;
}

}  // namespace gyrocal::analysis::testing
