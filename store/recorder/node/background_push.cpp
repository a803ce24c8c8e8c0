#include "store/recorder/node/background_push.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>

#include "lcmtypes/process/process_main.hpp"

extern char** environ;

namespace gyrocal::recorder::node {
namespace {

// Seconds the push waits for the run's stop to be committed (the recorder commits every
// --batch-ms; a database blocked by a storage fault may take longer: then the next push sends it).
constexpr const char* kWaitS = "120";

}  // namespace

BackgroundPush::BackgroundPush(std::string url, std::string db_path)
    : url_(std::move(url)),
      db_path_(std::move(db_path)),
      exe_(process::ExecutableDir() + "/gyrocal") {}

void BackgroundPush::RunEnded(const std::string& run_id) {
    if (enabled() && !run_id.empty()) pending_.push_back(run_id);
}

std::vector<std::string> BackgroundPush::Poll() {
    std::vector<std::string> log;
    for (auto it = running_.begin(); it != running_.end();) {
        int status = 0;
        if (waitpid(*it, &status, WNOHANG) == *it) {
            if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
                log.push_back("background push (pid " + std::to_string(*it) +
                              ") failed; the runs go with the next push");
            it = running_.erase(it);
        } else {
            ++it;
        }
    }
    for (const std::string& run : pending_) {
        std::vector<std::string> args = {exe_,           "push", "--db",     db_path_,
                                         "--wait-ended", run,    "--wait-s", kWaitS};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        // The environment, with the centre's URL in it (not on the command line).
        std::vector<std::string> env_text = {"GYROCAL_CENTRAL_URL=" + url_};
        for (char** e = environ; e && *e; ++e)
            if (std::strncmp(*e, "GYROCAL_CENTRAL_URL=", 20) != 0) env_text.emplace_back(*e);
        std::vector<char*> envp;
        for (auto& e : env_text) envp.push_back(e.data());
        envp.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, 2, 1);  // its report goes to our log
        pid_t pid = 0;
        const int rc = posix_spawn(&pid, exe_.c_str(), &actions, nullptr, argv.data(), envp.data());
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0) {
            log.push_back("cannot start '" + exe_ + "' to push run '" + run +
                          "': " + std::strerror(rc));
            continue;
        }
        running_.push_back(pid);
        log.push_back("run '" + run + "' ended: pushing it in the background (pid " +
                      std::to_string(pid) + ")");
    }
    pending_.clear();
    return log;
}

}  // namespace gyrocal::recorder::node
