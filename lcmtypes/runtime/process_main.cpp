#include "process_main.hpp"

#include <exception>
#include <iostream>

#include "shutdown.hpp"

namespace gyrocal {

std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv,
                                    const std::string& process,
                                    const std::function<std::string()>& validate) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << process << ": " << e.what() << " (see --help)\n";
        return 2;
    }
    if (const std::string err = validate ? validate() : ""; !err.empty()) {
        std::cerr << process << ": " << err << "\n";
        return 2;
    }
    return std::nullopt;
}

int RunUntilStopped(const std::string& process, const std::function<void()>& run) {
    try {
        InstallStopHandlers();
        run();
    } catch (const std::exception& e) {
        std::cerr << process << ": " << e.what() << "\n";
        return 1;
    }
    return 0;
}

}  // namespace gyrocal
