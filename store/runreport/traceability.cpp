#include "store/runreport/traceability.hpp"

#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::runreport {

namespace {

std::string Text(const nlohmann::json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_array()) {
        std::string s;
        for (const auto& e : v) s += (s.empty() ? "" : ", ") + Text(e);
        return s.empty() ? "none" : s;
    }
    if (v.is_number_float()) return text::Sig(v.get<double>(), 4);
    return v.dump();
}

void Add(DataSource& s, const nlohmann::json& c, const std::string& key, const std::string& label) {
    const auto it = c.find(key);
    if (it != c.end() && !it->is_null()) s.details.push_back({label, Text(*it)});
}

}  // namespace

DataSource SourceOf(const db::RunInfo& run) {
    DataSource s;
    const auto c = nlohmann::json::parse(run.config_json, nullptr, false);
    if (!c.is_object() || !c.contains("source")) {
        s.kind = "not recorded";
        s.details.push_back(
            {"configuration", run.config_json.empty()
                                  ? "none recorded with the run"
                                  : "recorded without a source: " + run.config_json});
        return s;
    }
    const std::string source = Text(c["source"]);
    if (source == "sim") {
        s.kind = "simulated rig";
        Add(s, c, "seed", "seed");
        Add(s, c, "noise_seed", "noise seed (0 = seed)");
        Add(s, c, "preset", "module preset");
        Add(s, c, "sensors", "units");
        Add(s, c, "effects", "undeclared effects switched on");
        Add(s, c, "profile", "profile");
        if (c.contains("setpoints_c") && c["setpoints_c"].is_array() && !c["setpoints_c"].empty())
            Add(s, c, "setpoints_c", "setpoints [degC]");
    } else if (source == "csv" || source == "log") {
        s.kind = source == "csv" ? "CSV file" : "LCM log";
        Add(s, c, "input", "file");
        if (c.contains("input_sha256"))
            Add(s, c, "input_sha256", "SHA-256");
        else
            s.details.push_back({"SHA-256", "not recorded (run made before gyrocal recorded it)"});
    } else if (source == "lines") {
        s.kind = "line stream";
        s.details.push_back(
            {"input", "standard input of gyrocal calibrate (a DAQ stream; nothing to hash)"});
    } else {
        s.kind = source;
    }
    Add(s, c, "plateau_slow_noise_dps", "plateau slow noise [deg/s]");
    Add(s, c, "speed", "speed (0 = auto)");
    Add(s, c, "lcm_url", "LCM URL");
    return s;
}

std::vector<std::pair<std::string, std::string>> Hosts(const db::RunDetail& d) {
    std::map<std::string, std::set<std::string>> roles;
    if (!d.run.host.empty()) roles[d.run.host].insert("run announced");
    if (!d.run.recorder_host.empty()) roles[d.run.recorder_host].insert("gyrocal-recorder");
    for (const auto& p : d.processes)
        if (!p.host.empty()) roles[p.host].insert(p.process);
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [host, what] : roles) {
        std::string list;
        for (const auto& w : what) list += (list.empty() ? "" : ", ") + w;
        out.push_back({host, list});
    }
    return out;
}

std::string OutcomeText(const db::RunInfo& run) {
    if (run.outcome.empty()) return "not recorded";
    return run.outcome + (run.reason.empty() ? "" : ": " + run.reason);
}

}  // namespace gyrocal::runreport
