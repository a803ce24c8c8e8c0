#include "tools/supervisor/final_verdict.hpp"

#include "lcmtypes/text/number.hpp"

namespace gyrocal::supervisor {

namespace {

std::string Published(const coeff_set_t& c) {
    auto model = [](const model_t& m) {
        return text::Printf("%s with %d terms over %.1f..%.1f C", m.method.c_str(), m.num_terms,
                            m.temp_min_c, m.temp_max_c);
    };
    return "set " + std::to_string(c.coeff_set_id) + ": offset " + model(c.offset) +
           ", sensitivity " + model(c.sensitivity);
}

}  // namespace

bool FinalVerdict::AllComplete() const {
    for (const std::string& id : sensors) {
        auto it = final_reports.find(id);
        if (it == final_reports.end() || it->second.status != "complete") return false;
    }
    return !sensors.empty();
}

std::map<std::string, std::string> FinalVerdict::Labels() const {
    std::map<std::string, std::string> out;
    for (const auto& [id, c] : newest) {
        auto it = final_reports.find(id);
        if (it == final_reports.end() || !final_sets.count(id))
            out[id] = "NOT FINAL: published before the run's end; no final set arrived";
        else if (it->second.status != "complete")
            out[id] = "PARTIAL: " + it->second.reason;
        else if (it->second.coeff_set_id != c.coeff_set_id)
            out[id] = "NOT FINAL: a newer set than the final report's arrived";
        else
            out[id] = "";
    }
    return out;
}

std::string FinalVerdict::Explain() const {
    std::string out;
    for (const std::string& id : sensors) {
        auto rep = final_reports.find(id);
        auto set = newest.find(id);
        if (rep != final_reports.end() && rep->second.status == "complete") continue;
        out += "gyrocal calibrate: unit " + id + ": ";
        if (rep == final_reports.end()) {
            out += "no final report from the fitter (did it run to the end?)";
        } else if (rep->second.status == "none") {
            out += "no calibration: " + rep->second.reason;
        } else {
            out += "PARTIAL calibration: " + rep->second.reason;
        }
        if (set != newest.end() && final_sets.count(id))
            out += "; published " + Published(set->second);
        else if (set != newest.end())
            out += "; the newest set (" + Published(set->second) + ") is from before the run's end";
        else
            out += "; nothing published";
        out += "\n";
    }
    return out;
}

}  // namespace gyrocal::supervisor
