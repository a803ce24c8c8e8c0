#include "processors/model/inputs.hpp"

#include <limits>

namespace gyrocal::model {

gyrocal_tracker_config_t TrackerConfigFor(const std::vector<const Model*>& models) {
    gyrocal_tracker_config_t c = gyrocal_tracker_config_default();
    double tau = 0.0, width = 0.0;  // 0 = not named yet
    auto adopt = [](double* have, double want, const char* what) {
        if (*have != 0.0 && *have != want)
            throw ModelError(std::string("terms need two different ") + what + " (" +
                             std::to_string(*have) + " and " + std::to_string(want) +
                             "): a coefficient set tracks each input once");
        *have = want;
    };
    for (const Model* m : models) {
        for (const ResolvedTerm& t : ResolveTerms(m->term_names)) {
            if (t.c.kind == GYROCAL_TERM_DTDT || t.c.kind == GYROCAL_TERM_DT_DTDT)
                adopt(&tau, t.c.param > 0.0 ? t.c.param : GYROCAL_DEFAULT_RATE_TAU_S,
                      "dT/dt time constants");
            if (t.c.kind == GYROCAL_TERM_HEATING)
                adopt(&width, GYROCAL_SIGN_BRANCH_WIDTH_C, "branch widths");
            if (t.c.kind == GYROCAL_TERM_BRANCH) adopt(&width, t.c.param, "branch widths");
        }
    }
    if (tau != 0.0) c.rate_tau_s = tau;
    if (width != 0.0) c.branch_width_c = width;
    return c;
}

gyrocal_tracker_config_t TrackerConfigFor(const Model& model) { return TrackerConfigFor({&model}); }

InputTracker::InputTracker(gyrocal_tracker_config_t config) {
    gyrocal_tracker_init(&state_, config);
}

void InputTracker::PowerOn(int64_t power_on_utime) {
    gyrocal_tracker_power_on(&state_, power_on_utime);
}

ModelInputs InputTracker::Update(int64_t utime, double temp_c, double supply_v) {
    ModelInputs in;
    gyrocal_tracker_update(&state_, utime, temp_c, supply_v, &in);
    return in;
}

ModelInputs SteadyStateInputs(const Model& model, double temp_c) {
    const gyrocal_tracker_config_t c = TrackerConfigFor(model);
    ModelInputs in;
    in.temp_c = temp_c;
    in.dtemp_dt_c_per_s = 0.0;
    in.rate_tau_s = c.rate_tau_s;
    in.supply_v = kNominalSupplyV;
    in.branch = 0.0;
    in.heating = 0.0;
    in.branch_width_c = c.branch_width_c;
    in.direction = 0.0;
    in.time_since_power_s = std::numeric_limits<double>::infinity();
    return in;
}

}  // namespace gyrocal::model
