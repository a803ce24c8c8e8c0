#include "lcmtypes/process/process_main.hpp"

#include <unistd.h>

#include <exception>
#include <iostream>

#include "lcmtypes/process/shutdown.hpp"

namespace gyrocal::process {

std::string ErrorLine(const std::string& process, const std::string& what) {
    return process + kErrorTag + what;
}

void PrintError(const std::string& process, const std::string& what) {
    std::cerr << ErrorLine(process, what) << "\n";
}

bool IsErrorLineOf(const std::string& process, const std::string& line) {
    return line.rfind(process + kErrorTag, 0) == 0;
}

std::string ExecutableDir() {
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return ".";
    const std::string p(buf, static_cast<size_t>(n));
    const auto slash = p.rfind('/');
    return slash == std::string::npos ? "." : p.substr(0, slash);
}

std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv,
                                    const std::string& process,
                                    const std::function<std::string()>& validate) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        PrintError(process, std::string(e.what()) + " (see --help)");
        return 2;
    }
    if (const std::string err = validate ? validate() : ""; !err.empty()) {
        PrintError(process, err);
        return 2;
    }
    if (CheckOnly()) return 0;  // the command line is valid; run nothing
    return std::nullopt;
}

int RunUntilStopped(const std::string& process, const std::function<void()>& run) {
    try {
        InstallStopHandlers();
        run();
    } catch (const std::exception& e) {
        PrintError(process, e.what());
        return 1;
    }
    return 0;
}

}  // namespace gyrocal::process
