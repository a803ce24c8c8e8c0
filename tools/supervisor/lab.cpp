#include "tools/supervisor/lab.hpp"

#include <array>
#include <stdexcept>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/text/names.hpp"

namespace gyrocal::supervisor {
namespace {

constexpr std::array<std::string_view, 5> kProducers = {"gyrocal-sim-rig", "gyrocal-sequencer",
                                                        "gyrocal-csv-source", "gyrocal-line-source",
                                                        "gyrocal-log-source"};
constexpr std::array<std::string_view, 4> kProcessors = {"gyrocal-plateau", "gyrocal-rotation",
                                                         "gyrocal-fitter", "gyrocal-compensator"};

template <size_t N>
bool In(const std::array<std::string_view, N>& set, std::string_view name) {
    for (std::string_view s : set)
        if (s == name) return true;
    return false;
}

constexpr text::NameTable<Role, 4> kRoleNames{{{Role::kAll, "all"},
                                               {Role::kProducers, "producers"},
                                               {Role::kProcessors, "processors"},
                                               {Role::kRecorder, "recorder"}}};

}  // namespace

std::optional<Role> ParseRole(std::string_view name) { return text::ValueOf(kRoleNames, name); }

const char* RoleName(Role role) { return text::NameOf(kRoleNames, role); }

bool RoleRuns(Role role, std::string_view process) {
    switch (role) {
        case Role::kAll:
            return In(kProducers, process) || In(kProcessors, process) ||
                   process == "gyrocal-recorder";
        case Role::kProducers:
            return In(kProducers, process);
        case Role::kProcessors:
            return In(kProcessors, process);
        case Role::kRecorder:
            return process == "gyrocal-recorder";
    }
    return false;
}

OnCrash CrashPolicy(std::string_view process) {
    if (process == "gyrocal-sequencer" || process == "gyrocal-recorder" || In(kProcessors, process))
        return OnCrash::kRestart;
    return OnCrash::kAbortRun;
}

Recovery RecoveryOf(std::string_view process) {
    if (process == "gyrocal-fitter") return Recovery::kStoredPoints;
    if (process == "gyrocal-compensator") return Recovery::kStoredCoeffs;
    if (process == "gyrocal-sequencer") return Recovery::kResumeSequence;
    return Recovery::kNone;
}

bool RestartBudget::Take(const std::string& process) {
    int& n = used_[process];
    if (n >= max_) return false;
    ++n;
    return true;
}

int RestartBudget::used(const std::string& process) const {
    auto it = used_.find(process);
    return it == used_.end() ? 0 : it->second;
}

std::string ChamberUrl(const std::string& url, int chamber) {
    if (chamber < 1 || chamber > 100)
        throw std::invalid_argument("--chamber " + std::to_string(chamber) + ": valid is 1..100");
    if (chamber == 1) return url;
    std::optional<bus::UdpmAddress> a = bus::ParseUdpm(url);
    if (!a)
        throw std::invalid_argument("--chamber " + std::to_string(chamber) +
                                    " needs a udpm:// LCM URL with a port "
                                    "to offset, not '" +
                                    url + "'");
    a->port += chamber - 1;
    if (a->port > 65535)
        throw std::invalid_argument("--chamber " + std::to_string(chamber) + ": port " +
                                    std::to_string(a->port) + " of '" + url + "' is past 65535");
    return bus::FormatUdpm(*a);
}

}  // namespace gyrocal::supervisor
