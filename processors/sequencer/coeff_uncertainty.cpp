#include "processors/sequencer/coeff_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processors/model/inputs.hpp"

namespace gyrocal::sequencer {

CoeffUncertainty UncertaintyOver(const model::CoeffSet& set, double min_c, double max_c) {
    if (!std::isfinite(min_c) || !std::isfinite(max_c) || min_c > max_c)
        throw std::invalid_argument("uncertainty range [" + std::to_string(min_c) + ", " +
                                    std::to_string(max_c) + "] degC: needs finite min <= max");
    const model::Evaluator offset(set.offset);
    const model::Evaluator sens(set.sensitivity);
    CoeffUncertainty u{0.0, 0.0};
    const int steps = std::max(1, static_cast<int>(std::ceil(max_c - min_c)));
    for (int i = 0; i <= steps; ++i) {
        const double t_c = min_c + (max_c - min_c) * i / steps;
        const auto o = offset.Evaluate(model::SteadyStateInputs(set.offset, t_c),
                                       model::RangePolicy::kExtrapolate);
        const auto s = sens.Evaluate(model::SteadyStateInputs(set.sensitivity, t_c),
                                     model::RangePolicy::kExtrapolate);
        const double s_abs = std::abs(s.value);
        const double off = std::sqrt(o.variance) / s_abs;
        const double pct = 100.0 * std::sqrt(s.variance) / s_abs;
        if (!std::isfinite(off) || !std::isfinite(pct)) return CoeffUncertainty{};
        u.offset_dps = std::max(u.offset_dps, off);
        u.sensitivity_pct = std::max(u.sensitivity_pct, pct);
    }
    return u;
}

}  // namespace gyrocal::sequencer
