#pragma once
// The frame of a process's main(): the same exit codes and messages in every process, so a script
// or the launcher tells a bad option (2) from a failure (1), and each message names its process.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

namespace gyrocal::process {

// The one shape of every process's fatal message, so the launcher can surface it as it is:
//   "<process>: error: <where>: <what>; <what would be valid>"
// (where = the file:line, option, channel or device). ErrorLine builds it; PrintError writes it
// to stderr; IsErrorLineOf tells a launcher which lines of a child's log are its errors.
inline constexpr const char* kErrorTag = ": error: ";
std::string ErrorLine(const std::string& process, const std::string& what);
void PrintError(const std::string& process, const std::string& what);
bool IsErrorLineOf(const std::string& process, const std::string& line);

// GYROCAL_CHECK_ONLY=1 in the environment: every command parses and checks its command line as
// usual, then runs nothing and exits 0 (2 for a bad option, as always). The docs test
// (tests/docs) runs every example command of the guide this way, so the guide cannot drift from
// the command lines.
inline bool CheckOnly() {
    const char* v = std::getenv("GYROCAL_CHECK_ONLY");
    return v != nullptr && std::string(v) == "1";
}

// The folder of this process's executable (/proc/self/exe), where its sibling executables are;
// "." when it cannot be read.
std::string ExecutableDir();

// The --help footer of a process that runs until stopped (RunUntilStopped's exit codes).
inline constexpr const char* kNodeExitCodes =
    "Exit codes: 0 normal stop (SIGINT/SIGTERM), 1 runtime failure (e.g. LCM cannot open),\n"
    "            2 bad options.";

// Parses argv into what `app` binds, then asks `validate` ("" when the options are valid, else a
// one-line error naming the option; none when the options' own checks suffice). Returns the exit
// code when the process must end now: 0 after --help, 2 for a bad option (on stderr as
// "<process>: error: <what>"); nullopt to go on.
std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv,
                                    const std::string& process,
                                    const std::function<std::string()>& validate = {});

// Installs the SIGINT/SIGTERM handlers, then runs the node: 0 when `run` returns (it was
// stopped), 1 when it throws (on stderr as "<process>: error: <what>").
int RunUntilStopped(const std::string& process, const std::function<void()>& run);

// The whole main() of a node process whose options come from Options::Defaults(), `add_options`
// and `std::string Options::Validate()`, and that runs Node(options) until stopped: --help shows
// `description`, every option's default and kNodeExitCodes; the exit codes and messages are
// ParseCommandLine's and RunUntilStopped's.
template <class Node, class Options>
int NodeMain(int argc, char** argv, const std::string& process, const std::string& description,
             void (*add_options)(CLI::App&, Options&)) {
    Options options = Options::Defaults();
    CLI::App app{description, process};
    app.footer(kNodeExitCodes);
    app.option_defaults()->always_capture_default();
    add_options(app, options);
    if (auto exit_code =
            ParseCommandLine(app, argc, argv, process, [&] { return options.Validate(); }))
        return *exit_code;
    return RunUntilStopped(process, [&] { Node(options).Run(); });
}

}  // namespace gyrocal::process
