#include "tools/cli/cmd_spy.hpp"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tools/supervisor/paths.hpp"

namespace gyrocal::cli {
namespace {

struct SpyOptions {
    std::string lcm_url;
    std::string java = "java";
    std::string lcm_jar = "/usr/share/java/lcm.jar";
    std::string jchart_jar = "/usr/share/java/jchart2d.jar";
};

int RunSpy(const SpyOptions& o) {
    const std::string types = supervisor::TypesJar();
    struct Need {
        std::string what, path, fix;
    };
    for (const Need& n :
         {Need{"LCM's Java library", o.lcm_jar, "apt-get install liblcm-java"},
          Need{"jchart2d (lcm-spy's charts)", o.jchart_jar, "apt-get install libjchart2d-java"},
          Need{"the gyrocal types jar", types, "build the project (tools/run.sh setup)"}}) {
        if (!std::filesystem::exists(n.path)) {
            std::cerr << "gyrocal spy: " << n.what << " not found at " << n.path << ": " << n.fix
                      << "\n";
            return 1;
        }
    }
    if (launch::FindOnPath(o.java).empty()) {
        std::cerr << "gyrocal spy: '" << o.java << "' not found: apt-get install default-jre\n";
        return 1;
    }
    const std::string url = bus::BusOptions{o.lcm_url}.ResolvedUrl();
    std::vector<std::string> args = {o.java,
                                     "-Djava.net.preferIPv4Stack=true",
                                     "-Xmx256m",
                                     "-cp",
                                     o.lcm_jar + ":" + o.jchart_jar + ":" + types,
                                     "lcm.spy.Spy",
                                     "--lcm-url=" + url};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::cerr << "gyrocal spy: cannot start " << o.java << "\n";
    return 1;
}

}  // namespace

void AddSpyCommand(CLI::App& app, std::function<int()>& action) {
    auto o = std::make_shared<SpyOptions>();
    CLI::App* cmd =
        app.add_subcommand("spy", "watch the bus live in lcm-spy, with every gyrocal type decoded");
    cmd->add_option("--lcm-url", o->lcm_url, "LCM URL (default: $GYROCAL_LCM_URL or udpm TTL 0)");
    cmd->add_option("--java", o->java, "java executable")->capture_default_str();
    cmd->footer(
        "Needs a display (X11). Exit codes: 1 when java, lcm.jar, jchart2d.jar or the types jar is "
        "missing; otherwise lcm-spy's own.");
    cmd->callback([o, &action] { action = [o] { return RunSpy(*o); }; });
}

}  // namespace gyrocal::cli
