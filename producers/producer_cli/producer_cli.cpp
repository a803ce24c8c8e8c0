#include "producers/producer_cli/producer_cli.hpp"

#include "lcmtypes/process/renamed_option.hpp"

namespace gyrocal::producer_cli {

void AddLcmUrlOption(CLI::App& app, std::string& lcm_url) {
    app.add_option("--lcm-url", lcm_url,
                   "LCM URL (default $GYROCAL_LCM_URL, else udpm://239.255.76.67:7667?ttl=0)");
}

CLI::Option* AddOpeningOptions(CLI::App& app, const std::string& footer, const std::string& name,
                               std::string& target, const std::string& help, bool required,
                               std::string& lcm_url) {
    app.footer(footer);
    CLI::Option* first = app.add_option(name, target, help)->required(required);
    AddLcmUrlOption(app, lcm_url);
    return first;
}

void AddConversionOptions(CLI::App& app, csv::ConversionOptions& conversion,
                          const std::string& start_utime_help) {
    app.add_option("--start-utime", conversion.start_utime, start_utime_help);
    app.add_option("--preset", conversion.preset,
                   "gyro module preset for the temperature transfer: 610|613 (default 610)");
    app.add_option("--temp-v-at-25c", conversion.temp_v_at_25c,
                   "temperature output at 25 degC [V] (preset: 2.5), -10..10");
    CLI::Option* slope = app.add_option("--temp-v-per-c", conversion.temp_v_per_c,
                                        "temperature output slope [V/degC] (preset: 0.009), > 0 "
                                        "and <= 1");
    process::AddOldOptionName<double>(app, slope, "--temp-v-per-k", conversion.temp_v_per_c);
    app.add_option("--encoder-counts-per-rev", conversion.encoder_counts_per_rev,
                   "encoder counts per revolution incl. quadrature (default 20000), >= 1");
}

}  // namespace gyrocal::producer_cli
