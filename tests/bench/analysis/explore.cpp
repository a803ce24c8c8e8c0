#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/report.hpp"
#include "tests/processors/analysis/sim_run.hpp"
using namespace gyrocal;
int main(int argc, char** argv) {
    analysis::testing::SimRunOptions o;
    int seeds = argc > 2 ? atoi(argv[2]) : 3;
    std::string eff = argc > 1 ? argv[1] : "none";
    for (int i = 3; i < argc; ++i) sim::ParseEffect(o.effects, argv[i]);
    if (getenv("SENSOR_TAU")) o.sensor_tau_s = atof(getenv("SENSOR_TAU"));
    if (getenv("PKG_TAU")) o.package_tau_s = atof(getenv("PKG_TAU"));
    if (getenv("SP")) {
        o.setpoints_c.clear();
        std::string sp = getenv("SP");
        size_t pos = 0;
        while (pos < sp.size()) {
            size_t e = sp.find(',', pos);
            if (e == std::string::npos) e = sp.size();
            o.setpoints_c.push_back(atof(sp.substr(pos, e - pos).c_str()));
            pos = e + 1;
        }
    }
    for (int s = 1; s <= seeds; ++s) {
        o.seed = s + (getenv("SEED0") ? atoi(getenv("SEED0")) : 0);
        auto t0 = std::chrono::steady_clock::now();
        auto run = analysis::testing::MakeSimRun(o);
        auto t1 = std::chrono::steady_clock::now();
        analysis::AnalysisOptions ao;
        if (getenv("HAC")) ao.hac_lag_s = atof(getenv("HAC"));
        if (getenv("Z2")) ao.min_z2 = atof(getenv("Z2"));
        if (getenv("CVG")) ao.min_cv_gain = atof(getenv("CVG"));
        auto r = analysis::Analyze(run.run, ao);
        auto t2 = std::chrono::steady_clock::now();
        std::printf("seed %d sim %.2fs analyze %.2fs dur %.0fs o1=%g o2=%g\n", s,
                    std::chrono::duration<double>(t1 - t0).count(),
                    std::chrono::duration<double>(t2 - t1).count(), run.duration_s,
                    run.truth.offset_coeffs[1], run.truth.offset_coeffs[2]);
        std::printf("%s", analysis::FormatReport(r).c_str());
    }
}
