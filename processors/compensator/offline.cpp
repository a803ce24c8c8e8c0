#include "processors/compensator/offline.hpp"

#include <nlohmann/json.hpp>

#include "lcmtypes/text/number.hpp"
#include "processors/model/json.hpp"

namespace gyrocal::compensator {

namespace {

std::string Known(const std::map<std::string, model::CoeffSet>& sets) {
    std::string s;
    for (const auto& [id, set] : sets) s += (s.empty() ? "" : ", ") + id;
    return s.empty() ? "none" : s;
}

}  // namespace

OfflineResult CompensateRows(const std::vector<csv::CsvRow>& rows,
                             const std::map<std::string, model::CoeffSet>& sets,
                             const std::string& csv_file, const std::string& coeff_origin,
                             const OfflineOptions& o) {
    OfflineResult res;
    csv::MessageBuilder builder;
    std::map<std::string, SensorCompensator> comps;
    for (const csv::CsvRow& row : rows) {
        auto it = comps.find(row.sensor_id);
        if (it == comps.end()) {
            const auto set = sets.find(row.sensor_id);
            if (set == sets.end())
                throw OfflineError(csv_file + ":" + std::to_string(row.line) + ": sensor_id '" +
                                   row.sensor_id + "' has no coefficient set in " + coeff_origin +
                                   " (sets for: " + Known(sets) + ")");
            it = comps.emplace(row.sensor_id, SensorCompensator(o.core)).first;
            const SetResult sr = it->second.SetCoefficients(set->second);
            if (sr.outcome == SetOutcome::kRejected)
                throw OfflineError(coeff_origin + ": coefficient set " +
                                   std::to_string(set->second.coeff_set_id) + " of sensor '" +
                                   row.sensor_id + "' refused: " + sr.detail);
        }
        // The message a CSV source publishes for this row, handed over as the live node does.
        const csv::RowMessages msgs =
            builder.Build(row, csv::StreamUtime(o.start_utime, row.time_s));
        if (msgs.power) it->second.PowerOn(msgs.power->power_on_utime);
        const gyro_sample_t& m = msgs.gyro;
        const ApplyResult r = it->second.Apply(SampleOf(m));
        if (r.status != ApplyStatus::kOk) {
            if (res.skipped++ == 0)
                res.first_skip = "line " + std::to_string(row.line) + " (sensor " + row.sensor_id +
                                 "): " + ToString(r.status) +
                                 (r.detail.empty() ? "" : ": " + r.detail);
            continue;
        }
        res.rates.push_back({row.line, row.time_s, row.sensor_id, r.out.rate_dps, r.out.angle_deg,
                             m.temp_c, static_cast<int>(r.out.range), r.out.coeff_set_id});
    }
    return res;
}

std::map<std::string, model::CoeffSet> CoeffSetsFromJson(const std::string& text,
                                                         const std::string& file) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw OfflineError(file + ": not valid JSON (byte " + std::to_string(e.byte) +
                           "): " + e.what());
    }
    std::vector<std::pair<std::string, const nlohmann::json*>> items;  // (field path, set)
    if (j.is_object() && j.contains("coeff_sets")) {
        if (!j["coeff_sets"].is_array())
            throw OfflineError(file + ": field 'coeff_sets' must be an array of coefficient sets");
        for (size_t i = 0; i < j["coeff_sets"].size(); ++i)
            items.push_back({"coeff_sets[" + std::to_string(i) + "]", &j["coeff_sets"][i]});
    } else if (j.is_object() && j.contains("offset")) {
        items.push_back({"(top level)", &j});
    } else {
        throw OfflineError(file +
                           ": expected the export format ({\"coeff_sets\": [...]}, as `gyrocal "
                           "export --format json` writes) or one coefficient set object");
    }
    if (items.empty()) throw OfflineError(file + ": 'coeff_sets' is empty");
    std::map<std::string, model::CoeffSet> sets;
    for (const auto& [where, item] : items) {
        model::CoeffSet set;
        try {
            set = model::CoeffSetFromJson(*item);
        } catch (const std::exception& e) {
            throw OfflineError(file + ": " + where + ": " + e.what());
        }
        if (set.sensor_id.empty()) throw OfflineError(file + ": " + where + ".sensor_id is empty");
        if (!sets.emplace(set.sensor_id, set).second)
            throw OfflineError(file + ": " + where + ": a second coefficient set for sensor '" +
                               set.sensor_id + "' (give one set per sensor)");
    }
    return sets;
}

std::string FormatRatesCsv(const std::vector<OfflineRate>& rates) {
    std::string out = "time_s,sensor_id,rate_dps,angle_deg,temp_c,range_flag\n";
    for (const OfflineRate& r : rates) {
        // time_s on the microsecond grid of utime
        out += text::Printf("%.6f", r.time_s) + "," + r.sensor_id + "," +
               text::Sig(r.rate_dps, 17) + "," + text::Sig(r.angle_deg, 17) + "," +
               text::Sig(r.temp_c, 17) + "," + std::to_string(r.range_flag) + "\n";
    }
    return out;
}

}  // namespace gyrocal::compensator
