#pragma once
// `gyrocal validate RUN (--model-run RUN2 | --coeff-set-row N | --coeffs FILE) [--sensor ID]
//  [--db FILE] [--json] [--no-store] [--bin-s S]`: applies a stored model to another run of the
// same unit and reports the error on its still data against that run's floor
// (analysis/validate.hpp), stored with the validated run (table validations).
// Exit codes: 0 validated (whatever the figures), 1 failure (database, run, sensor or model
// missing or unusable), 2 bad options.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>

namespace gyrocal::cli {

struct ValidateOptions {
    std::string run_id;  // the run to validate on
    std::string db = "gyrocal.db";
    std::string sensor_id;                 // "" = every sensor the model covers in the run
    std::string model_run_id;              // the newest set of each sensor of this run
    std::optional<int64_t> coeff_set_row;  // or this stored set
    std::string coeffs_path;               // or the sets of this JSON export
    double bin_s = 10.0;                   // [s]
    bool json = false;
    bool store = true;
    std::string command_line;
};

int RunValidate(const ValidateOptions& options, std::ostream& out, std::ostream& err);
void AddValidateCommand(CLI::App& app, std::function<int()>& action);

}  // namespace gyrocal::cli
