// gyrocal-othersim: writes a measured-looking calibration run (CSV import format) and its truth
// JSON, from a rig of another design than producers/sim (see options.hpp and README.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "lcmtypes/process/process_main.hpp"
#include "tests/support/othersim/cli.hpp"
#include "tests/support/othersim/generator.hpp"

int main(int argc, char** argv) {
    using namespace gyrocal::othersim;
    Options o;
    CliValues v;
    CLI::App app{"gyrocal-othersim: an independent simulated lab run as a CSV file plus its truth",
                 "gyrocal-othersim"};
    app.footer("Exit codes: 0 written, 1 a file could not be written, 2 bad options.");
    AddOptions(app, o, v);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::fprintf(stderr, "gyrocal-othersim: %s (see --help)\n", e.what());
        return 2;
    }
    if (const std::string problem = Finish(o, v); !problem.empty()) {
        std::fprintf(stderr, "gyrocal-othersim: %s (see --help)\n", problem.c_str());
        return 2;
    }
    if (gyrocal::process::CheckOnly()) return 0;  // GYROCAL_CHECK_ONLY=1: the command line is valid
    try {
        const Generated g = WriteRun(o, v.out, v.truth_out);
        std::printf(
            "gyrocal-othersim: %lld rows, %.0f s of data, %zu dwells, %zu turns -> %s, %s\n",
            static_cast<long long>(g.rows), g.timeline.duration_s, g.timeline.dwells.size(),
            g.timeline.turns.size(), v.out.c_str(), v.truth_out.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gyrocal-othersim: %s\n", e.what());
        return 1;
    }
    return 0;
}
