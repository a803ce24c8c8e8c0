#include "processors/fit/repeatability.hpp"

#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/fit_util.hpp"

namespace gyrocal::fit {

using namespace detail;

namespace {

int Approach(const std::vector<FitPoint>& pts, size_t i) {
    if (i == 0) return 0;
    return pts[i - 1].inputs.temp_c < pts[i].inputs.temp_c ? 1 : -1;
}

std::string Verdict(const Repeat& r, double z_limit) {
    if (std::abs(r.z) <= z_limit) return "repeatable within " + text::Sig(z_limit, 2) + " sigma";
    std::string s = "not repeatable (" + text::Sig(r.z, 3) + " sigma): ";
    if (r.first_approach != 0 && r.second_approach != 0 && r.first_approach != r.second_approach)
        return s + "approached from " + (r.first_approach > 0 ? "colder" : "hotter") +
               " then from " + (r.second_approach > 0 ? "colder" : "hotter") +
               ", consistent with hysteresis";
    return s + "approached from the same side (or from the run's start), consistent with a drift";
}

}  // namespace

std::vector<Repeat> Repeatability(const std::vector<FitPoint>& points, const model::Model& offset,
                                  const model::Model& sensitivity, double tolerance_c,
                                  double z_limit) {
    std::vector<FitPoint> pts = points;
    std::sort(pts.begin(), pts.end(),
              [](const FitPoint& a, const FitPoint& b) { return a.id < b.id; });
    const model::Evaluator off(offset), sens(sensitivity);
    std::vector<Repeat> out;
    for (size_t j = 1; j < pts.size(); ++j) {
        // The latest earlier visit of this temperature, with another temperature in between.
        for (size_t i = j; i-- > 0;) {
            if (std::abs(pts[i].inputs.temp_c - pts[j].inputs.temp_c) > tolerance_c) continue;
            bool left = false;
            for (size_t k = i + 1; k < j; ++k)
                left = left || std::abs(pts[k].inputs.temp_c - pts[j].inputs.temp_c) > tolerance_c;
            if (!left) break;  // a replicate of the same visit, not a return
            Repeat r;
            r.first_id = pts[i].id;
            r.second_id = pts[j].id;
            r.first_temp_c = pts[i].inputs.temp_c;
            r.second_temp_c = pts[j].inputs.temp_c;
            r.temp_c = 0.5 * (r.first_temp_c + r.second_temp_c);
            r.first_approach = Approach(pts, i);
            r.second_approach = Approach(pts, j);
            const double model_step = off.Value(pts[j].inputs, model::RangePolicy::kExtrapolate) -
                                      off.Value(pts[i].inputs, model::RangePolicy::kExtrapolate);
            r.diff_v = pts[j].y - pts[i].y - model_step;
            r.diff_sigma_v = std::hypot(pts[i].sigma_y, pts[j].sigma_y);
            model::ModelInputs at;
            at.temp_c = r.temp_c;
            const double s = sens.Value(at, model::RangePolicy::kClip);
            r.diff_dps = r.diff_v / s;
            r.diff_sigma_dps = r.diff_sigma_v / std::abs(s);
            r.z = r.diff_v / r.diff_sigma_v;
            r.verdict = Verdict(r, z_limit);
            out.push_back(r);
            break;
        }
    }
    return out;
}

}  // namespace gyrocal::fit
