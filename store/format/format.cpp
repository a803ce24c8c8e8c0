// Human tables and JSON for runs, a run's detail and a sensor's history.
#include "store/format/format.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "processors/model/convert.hpp"
#include "store/format/format_util.hpp"
#include "store/format/show_fit.hpp"

namespace gyrocal::format {

using namespace detail;

std::string Printable(const std::string& s) {
    std::string out = s;
    for (char& c : out) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7f) c = '?';
    }
    return out;
}

std::optional<int64_t> ParseUtc(const std::string& text) {
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0;
    int n = 0;
    if (std::sscanf(text.c_str(), "%4d-%2d-%2d%n", &y, &mo, &d, &n) != 3 || n != 10) {
        return std::nullopt;
    }
    std::string tail = text.substr(10);
    if (!tail.empty()) {
        if (tail[0] != 'T' && tail[0] != ' ') return std::nullopt;
        int m = 0;
        const int got = std::sscanf(tail.c_str() + 1, "%2d:%2d%n:%2d%n", &h, &mi, &m, &s, &m);
        if (got < 2) return std::nullopt;
        const std::string after = tail.substr(1 + static_cast<size_t>(m));
        if (!(after.empty() || after == "Z")) return std::nullopt;
    }
    if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || s > 60 || y < 1970) {
        return std::nullopt;
    }
    std::tm tm{};
    tm.tm_year = y - 1900;
    tm.tm_mon = mo - 1;
    tm.tm_mday = d;
    tm.tm_hour = h;
    tm.tm_min = mi;
    tm.tm_sec = s;
    const std::time_t t = timegm(&tm);
    std::tm back{};
    gmtime_r(&t, &back);
    if (back.tm_mday != d) return std::nullopt;  // e.g. 2026-02-31
    return static_cast<int64_t>(t) * 1000000;
}

std::optional<std::vector<double>> ParseTemps(const std::string& text) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        size_t used = 0;
        double v = 0;
        try {
            v = std::stod(item, &used);
        } catch (...) {
            return std::nullopt;
        }
        while (used < item.size() && item[used] == ' ') ++used;
        if (used != item.size() || !std::isfinite(v)) return std::nullopt;
        out.push_back(v);
    }
    if (out.empty()) return std::nullopt;
    return out;
}

std::string RunsTable(const std::vector<db::RunInfo>& runs) {
    // The station column only where runs came from stations (a central database).
    bool stations = false;
    for (const auto& r : runs) stations = stations || !r.station.empty();
    std::vector<std::string> head = {"RUN",          "OUTCOME",    "FIRST SEEN (UTC)", "SENSORS",
                                     "GYRO SAMPLES", "PLATEAUS",   "SENS PTS",         "COEFF SETS",
                                     "SEQ GAPS",     "DECODE ERR", "QUEUE DROPS",      "VERSION"};
    if (stations) head.push_back("STATION");
    Table t(head);
    for (const auto& r : runs) {
        std::vector<std::string> row = {RunLabel(r.run_id),
                                        r.outcome,
                                        db::UtcText(r.first_recv_utime),
                                        Join(r.sensor_ids, ","),
                                        std::to_string(r.gyro_samples),
                                        std::to_string(r.plateaus),
                                        std::to_string(r.sensitivity_points),
                                        std::to_string(r.coeff_sets),
                                        std::to_string(r.seq_gaps),
                                        std::to_string(r.decode_errors),
                                        std::to_string(r.queue_drops),
                                        r.software_version};
        if (stations) row.push_back(r.station);
        t.Add(row);
    }
    return t.str();
}

static nlohmann::json RunJson(const db::RunInfo& r) {
    nlohmann::json j = GYROCAL_JSON_FIELDS(r, run_id, outcome, reason, started_utime, stopped_utime,
                                           first_recv_utime, software_version, command_line, host,
                                           recorder_version, recorder_host, sensor_ids);
    if (!r.station.empty()) j["station"] = r.station;
    j["counts"] = GYROCAL_JSON_FIELDS(r, gyro_samples, encoder_samples, chamber_states, plateaus,
                                      sensitivity_points, coeff_sets, raw_events);
    j["losses"] = GYROCAL_JSON_FIELDS(r, seq_gaps, decode_errors, queue_drops);
    return j;
}

nlohmann::json RunsJson(const std::vector<db::RunInfo>& runs) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& r : runs) a.push_back(RunJson(r));
    return a;
}

// Parsed JSON of a stored text column; the text itself when it is not JSON (never throws).
static nlohmann::json ParsedOrText(const std::string& text) {
    if (text.empty()) return nullptr;
    const auto j = nlohmann::json::parse(text, nullptr, false);
    return j.is_discarded() ? nlohmann::json(text) : j;
}

// "temp_rate,hysteresis": the effects of an analysis' added_json; "-" when none.
static std::string AddedEffects(const std::string& added_json) {
    const auto j = nlohmann::json::parse(added_json, nullptr, false);
    std::vector<std::string> names;
    if (j.is_array()) {
        for (const auto& e : j) {
            if (e.is_object() && e.contains("effect") && e["effect"].is_string()) {
                names.push_back(e["effect"].get<std::string>());
            }
        }
    }
    return names.empty() ? "-" : Join(names, ",");
}

static std::string BeforeAfter(double before, double after, int precision) {
    return text::SigOrDash(before, precision) + " -> " + text::SigOrDash(after, precision);
}

static const ProvenanceSummary* FindProv(const std::vector<ProvenanceSummary>& p, int64_t id) {
    for (const auto& s : p) {
        if (s.coeff_row_id == id) return &s;
    }
    return nullptr;
}

// The run's identity, provenance and what was recorded.
static void RunHeaderText(std::ostream& out, const db::RunDetail& d) {
    const db::RunInfo& r = d.run;
    out << "Run " << Printable(RunLabel(r.run_id)) << "\n";
    out << "  outcome:          " << Printable(r.outcome)
        << (r.reason.empty() ? "" : " (" + Printable(r.reason) + ")") << "\n";
    out << "  started_utime:    " << Opt(r.started_utime) << "\n";
    out << "  stopped_utime:    " << Opt(r.stopped_utime) << "\n";
    out << "  first seen (UTC): " << db::UtcText(r.first_recv_utime) << "\n";
    out << "  software_version: " << Printable(r.software_version) << "\n";
    out << "  host:             " << Printable(r.host) << "\n";
    out << "  command_line:     " << Printable(r.command_line) << "\n";
    out << "  recorder:         " << Printable(r.recorder_version) << " on "
        << Printable(r.recorder_host) << "\n";
    out << "  sensors:          " << Printable(Join(r.sensor_ids, ", ")) << "\n";
    out << "  recorded:         " << r.gyro_samples << " gyro samples, " << r.encoder_samples
        << " encoder samples, " << r.chamber_states << " chamber states, " << r.raw_events
        << " raw events, " << d.events.size() << " run events\n";
}

// The run configuration as recorded (pretty JSON when it parses).
static void ConfigText(std::ostream& out, const db::RunInfo& r) {
    out << "\nConfiguration\n";
    const auto cfg = nlohmann::json::parse(r.config_json, nullptr, false);
    if (r.config_json.empty()) {
        out << "  (none recorded)\n";
    } else if (cfg.is_discarded()) {
        out << "  (not JSON) " << Printable(r.config_json) << "\n";
    } else {
        std::istringstream lines(cfg.dump(2));
        for (std::string line; std::getline(lines, line);) out << "  " << Printable(line) << "\n";
    }
}

// Every plateau of the run.
static void PlateausText(std::ostream& out, const db::RunDetail& d) {
    out << "\nPlateaus (" << d.plateaus.size() << ")\n";
    if (!d.plateaus.empty()) {
        Table t({"SENSOR", "PLATEAU_ID", "SETPOINT_C", "TEMP_MEAN_C", "TEMP_SLOPE_C_PER_MIN",
                 "GYRO_MEAN_V", "GYRO_SEM_V", "N_SAMPLES", "SEQ_GAPS"});
        for (const auto& p : d.plateaus) {
            t.Add({p.sensor_id, std::to_string(p.plateau_id), text::SigOrDash(p.setpoint_c),
                   text::PrintfOrDash("%.3f", p.temp_mean_c),
                   text::SigOrDash(p.temp_slope_c_per_min, 3), text::SigOrDash(p.gyro_mean_v, 8),
                   text::SigOrDash(p.gyro_sem_v, 3), std::to_string(p.n_samples),
                   std::to_string(p.seq_gaps)});
        }
        out << t.str();
    }
}

// Every sensitivity point (rotation), accepted or not.
static void SensitivityPointsText(std::ostream& out, const db::RunDetail& d) {
    out << "\nSensitivity points (" << d.sensitivity_points.size() << ")\n";
    if (!d.sensitivity_points.empty()) {
        Table t({"SENSOR", "ROTATION_ID", "DIR", "TEMP_C", "ENCODER_ANGLE_DEG",
                 "SENSITIVITY_V_PER_DPS", "STDERR", "ACCEPTED"});
        for (const auto& s : d.sensitivity_points) {
            t.Add({s.sensor_id, std::to_string(s.rotation_id), std::to_string(s.direction),
                   text::PrintfOrDash("%.3f", s.temp_c), text::SigOrDash(s.encoder_angle_deg),
                   text::SigOrDash(s.sensitivity_v_per_dps, 8),
                   text::SigOrDash(s.sensitivity_stderr_v_per_dps, 3),
                   s.accepted ? "yes" : "no: " + s.reject_reason});
        }
        out << t.str();
    }
}

// Which set a plateau run's closed loop made and which it keeps beside it (model/convert.hpp).
static std::string SetRole(const db::RunDetail& d, const db::CoeffSetInfo& c) {
    if (c.set.source == model::kClosedLoopSource)
        return "  final set: every still sample, the terms the data confirm";
    if (c.set.source != model::kFitterSource) return "";
    for (const auto& o : d.coeff_sets)
        if (o.set.sensor_id == c.set.sensor_id && o.set.source == model::kClosedLoopSource)
            return "  plateau set: plateau means only (the final set is the closed loop's)";
    return "";
}

// The final set of each sensor and source, with what it came from.
static void CoeffSetsText(std::ostream& out, const db::RunDetail& d,
                          const std::vector<ProvenanceSummary>& provenance) {
    out << "\nCoefficient sets (final of each sensor and source: " << d.coeff_sets.size() << ")\n";
    for (const auto& c : d.coeff_sets) {
        out << "  " << Printable(c.set.sensor_id) << "  set " << c.set.coeff_set_id << " ("
            << Printable(c.set.source) << ")" << SetRole(d, c) << SetStatusLabel(d, c) << "\n";
        for (const auto* m : {&c.set.offset, &c.set.sensitivity}) {
            out << "    " << Printable(m->quantity) << ": " << Printable(Terms(*m))
                << "  T0=" << text::SigOrDash(m->t0_c) << " C, valid "
                << text::SigOrDash(m->temp_min_c) << ".." << text::SigOrDash(m->temp_max_c)
                << " C, rms " << text::SigOrDash(m->residual_rms, 3) << ", " << m->n_points
                << " points, " << Printable(m->method) << "\n";
        }
        if (const ProvenanceSummary* p = FindProv(provenance, c.coeff_row_id)) {
            int64_t found = 0, samples = 0;
            for (const auto& item : p->items) {
                found += item.item_found ? 1 : 0;
                samples += item.stored_samples;
            }
            out << "    from " << c.set.plateau_ids.size() << " plateaus and "
                << c.set.rotation_ids.size() << " rotations (" << found << " of " << p->items.size()
                << " found), " << samples << " raw gyro samples stored\n";
        }
    }
}

// The stored analyses, before -> after.
static void AnalysesText(std::ostream& out, const db::RunDetail& d) {
    out << "\nAnalyses (" << d.analyses.size() << ")\n";
    if (!d.analyses.empty()) {
        Table t({"ANALYSIS_ID", "SENSOR", "CREATED (UTC)", "OUTCOME", "VERDICT", "ADDED",
                 "OFFSET_RMS_V", "RATE_RMS_DPS", "DRIFT_DPH", "FLOOR_RATE_RMS_DPS",
                 "COEFF_ROW_ID"});
        for (const auto& a : d.analyses) {
            t.Add({std::to_string(a.analysis_id), a.sensor_id, db::UtcText(a.created_wall_utime),
                   a.outcome.value_or("-"), a.verdict, AddedEffects(a.added_json),
                   BeforeAfter(a.offset_rms_v_before, a.offset_rms_v_after, 3),
                   BeforeAfter(a.rate_rms_dps_before, a.rate_rms_dps_after, 3),
                   BeforeAfter(a.drift_dph_before, a.drift_dph_after, 3),
                   text::SigOrDash(a.floor_rate_rms_dps, 3), Opt(a.coeff_row_id)});
        }
        out << t.str();
        out << "  (before -> after, on held-out still data: the run's declared model -> the "
               "extended model; gyrocal analyze stores its set with source analysis:<ANALYSIS_ID>, "
               "the calibration's closed loop (gyrocal-fitter) its final set with source "
            << model::kClosedLoopSource << ")\n";
    }
}

// Loss by channel as the recorder counted it.
static void LossesText(std::ostream& out, const db::RunDetail& d) {
    out << "\nLosses\n";
    if (d.losses.empty()) {
        out << "  none recorded\n";
    } else {
        Table t({"CHANNEL", "SEQ_GAPS", "SEQ_BACKWARDS", "DECODE_ERRORS", "QUEUE_DROPS"});
        for (const auto& l : d.losses) {
            t.Add({l.channel.empty() ? "(recorder)" : l.channel, std::to_string(l.seq_gaps),
                   std::to_string(l.seq_backwards), std::to_string(l.decode_errors),
                   std::to_string(l.queue_drops)});
        }
        out << t.str();
    }
}

// The last STATUS of each process.
static void ProcessesText(std::ostream& out, const db::RunDetail& d) {
    out << "\nProcesses (last STATUS of each in this run: their own view of loss and refusals)\n";
    if (d.processes.empty()) {
        out << "  none recorded\n";
    } else {
        Table t({"PROCESS", "HOST", "PID", "STATE", "RECEIVED", "PUBLISHED", "DECODE_ERRORS",
                 "SEQ_GAPS", "QUEUE_DROPS", "REJECTED", "LAST_REJECT"});
        for (const auto& p : d.processes) {
            t.Add({p.process, p.host, std::to_string(p.pid), p.state, std::to_string(p.received),
                   std::to_string(p.published), std::to_string(p.decode_errors),
                   std::to_string(p.seq_gaps), std::to_string(p.queue_drops),
                   std::to_string(p.rejected), p.last_reject.substr(0, 60)});
        }
        out << t.str();
    }
}

std::string RunDetailText(const db::RunDetail& d,
                          const std::vector<ProvenanceSummary>& provenance) {
    const db::RunInfo& r = d.run;
    std::ostringstream out;
    RunHeaderText(out, d);
    ConfigText(out, r);
    PlateausText(out, d);
    SensitivityPointsText(out, d);
    CoeffSetsText(out, d, provenance);
    out << FitSectionsText(d);
    AnalysesText(out, d);
    LossesText(out, d);
    ProcessesText(out, d);
    return out.str();
}

// Every plateau with its window, counts and statistics.
static nlohmann::json PlateausJson(const db::RunDetail& d) {
    nlohmann::json plateaus = nlohmann::json::array();
    for (const auto& p : d.plateaus) {
        plateaus.push_back(GYROCAL_JSON_FIELDS(
            p, sensor_id, plateau_id, setpoint_c, start_utime, end_utime, first_seq, last_seq,
            n_samples, n_excluded_motion, seq_gaps, temp_mean_c, temp_std_c, temp_slope_c_per_min,
            gyro_mean_v, gyro_std_v, gyro_sem_v, supply_mean_v));
    }
    return plateaus;
}

// Every sensitivity point, accepted or not.
static nlohmann::json SensitivityPointsJson(const db::RunDetail& d) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& s : d.sensitivity_points) {
        points.push_back(GYROCAL_JSON_FIELDS(s, sensor_id, rotation_id, start_utime, end_utime,
                                             n_samples, direction, temp_c, encoder_angle_deg,
                                             sensitivity_v_per_dps, sensitivity_stderr_v_per_dps,
                                             accepted, reject_reason));
    }
    return points;
}

// The final sets with the provenance of each (what it was fitted from).
static nlohmann::json CoeffSetsJson(const db::RunDetail& d,
                                    const std::vector<ProvenanceSummary>& provenance) {
    nlohmann::json sets = nlohmann::json::array();
    for (const auto& c : d.coeff_sets) {
        nlohmann::json cj = CoeffSetJson(c);
        if (const ProvenanceSummary* p = FindProv(provenance, c.coeff_row_id)) {
            nlohmann::json items = nlohmann::json::array();
            for (const auto& it : p->items) {
                nlohmann::json item =
                    GYROCAL_JSON_FIELDS(it, kind, item_id, start_utime, end_utime, n_samples);
                item["found"] = it.item_found;
                item["stored_gyro_samples"] = it.stored_samples;
                items.push_back(item);
            }
            cj["provenance"] = items;
        }
        sets.push_back(cj);
    }
    return sets;
}

// Loss by channel as the recorder counted it.
static nlohmann::json LossesJson(const db::RunDetail& d) {
    nlohmann::json losses = nlohmann::json::array();
    for (const auto& l : d.losses) {
        losses.push_back(
            GYROCAL_JSON_FIELDS(l, channel, seq_gaps, seq_backwards, decode_errors, queue_drops));
    }
    return losses;
}

// The run events.
static nlohmann::json EventsJson(const db::RunDetail& d) {
    nlohmann::json events = nlohmann::json::array();
    for (const auto& e : d.events) {
        events.push_back(GYROCAL_JSON_FIELDS(e, utime, event, reason, setpoint_index, setpoint_c));
    }
    return events;
}

// The last STATUS of each process.
static nlohmann::json ProcessesJson(const db::RunDetail& d) {
    nlohmann::json procs = nlohmann::json::array();
    for (const auto& p : d.processes) {
        procs.push_back(GYROCAL_JSON_FIELDS(p, process, host, pid, state, received, published,
                                            decode_errors, seq_gaps, queue_drops, rejected,
                                            last_reject, utime));
    }
    return procs;
}

// The source of the set an analysis made: the stored set's (the closed loop's), else the one
// gyrocal analyze gives it.
static nlohmann::json CoeffSourceJson(const db::RunDetail& d, const db::AnalysisRow& a) {
    if (!a.coeff_row_id) return nullptr;
    for (const auto& c : d.coeff_sets)
        if (c.coeff_row_id == *a.coeff_row_id) return c.set.source;
    return db::AnalysisSource(a.analysis_id);
}

// The stored analyses with their before/after errors.
static nlohmann::json AnalysesJson(const db::RunDetail& d) {
    nlohmann::json analyses = nlohmann::json::array();
    for (const auto& a : d.analyses) {
        analyses.push_back(
            {{"analysis_id", a.analysis_id},
             {"sensor_id", a.sensor_id},
             {"created_wall_utime", a.created_wall_utime},
             {"software_version", a.software_version},
             {"command_line", a.command_line},
             {"verdict", a.verdict},
             {"outcome", a.outcome ? nlohmann::json(*a.outcome) : nlohmann::json(nullptr)},
             {"candidates", ParsedOrText(a.candidates_json)},
             {"added", ParsedOrText(a.added_json)},
             {"error_before",
              {{"offset_rms_v", JsonNumber(a.offset_rms_v_before)},
               {"rate_rms_dps", JsonNumber(a.rate_rms_dps_before)},
               {"drift_dph", JsonNumber(a.drift_dph_before)}}},
             {"error_after",
              {{"offset_rms_v", JsonNumber(a.offset_rms_v_after)},
               {"rate_rms_dps", JsonNumber(a.rate_rms_dps_after)},
               {"drift_dph", JsonNumber(a.drift_dph_after)}}},
             {"floor_rate_rms_dps", JsonNumber(a.floor_rate_rms_dps)},
             {"result", ParsedOrText(a.result_json)},
             {"coeff_row_id", OptJson(a.coeff_row_id)},
             {"coeff_source", CoeffSourceJson(d, a)}});
    }
    return analyses;
}

nlohmann::json RunDetailJson(const db::RunDetail& d,
                             const std::vector<ProvenanceSummary>& provenance) {
    nlohmann::json j = RunJson(d.run);
    const auto cfg = nlohmann::json::parse(d.run.config_json, nullptr, false);
    j["config"] = cfg.is_discarded() ? nlohmann::json(d.run.config_json) : cfg;
    j["plateaus"] = PlateausJson(d);
    j["sensitivity_points"] = SensitivityPointsJson(d);
    j["coeff_sets"] = CoeffSetsJson(d, provenance);
    j["loss_by_channel"] = LossesJson(d);
    j["events"] = EventsJson(d);
    j["processes"] = ProcessesJson(d);
    j["analyses"] = AnalysesJson(d);
    AddFitJson(j, d);
    return j;
}

std::string HistoryTable(const std::string& sensor_id, const std::vector<db::CoeffSetInfo>& sets,
                         const std::vector<double>& ref_temps_c) {
    std::ostringstream out;
    out << "Sensor " << Printable(sensor_id) << ": " << sets.size() << " coefficient set"
        << (sets.size() == 1 ? "" : "s")
        << "; change is against the previous set at the same temperature\n";
    // Across stations (a central database): which station each set came from.
    bool stations = false;
    for (const auto& s : sets) stations = stations || !s.station.empty();
    std::vector<std::string> head = {"RECORDED (UTC)", "RUN"};
    if (stations) head.push_back("STATION");
    for (const char* h : {"COEFF_SET_ID", "SOURCE", "TEMP_C", "OFFSET_V", "D_OFFSET_MV",
                          "SENSITIVITY_V_PER_DPS", "D_SENSITIVITY_PCT"})
        head.push_back(h);
    Table t(head);
    for (size_t k = 0; k < sets.size(); ++k) {
        const db::CoeffSetRow& c = sets[k].set;
        for (double temp : ref_temps_c) {
            const auto off = Eval(c.offset, temp);
            const auto sens = Eval(c.sensitivity, temp);
            std::string d_off = "-", d_sens = "-";
            if (k > 0) {
                const auto p_off = Eval(sets[k - 1].set.offset, temp);
                const auto p_sens = Eval(sets[k - 1].set.sensitivity, temp);
                if (off && p_off) d_off = text::SigOrDash((*off - *p_off) * 1e3, 4);
                if (sens && p_sens && *p_sens != 0)
                    d_sens = text::SigOrDash((*sens / *p_sens - 1) * 100, 4);
            }
            std::vector<std::string> row = {db::UtcText(c.recv_utime), RunLabel(c.run_id)};
            if (stations) row.push_back(sets[k].station);
            for (std::string v :
                 {std::to_string(c.coeff_set_id), c.source, text::SigOrDash(temp, 4),
                  off ? text::SigOrDash(*off, 8) : std::string("n/a"), d_off,
                  sens ? text::SigOrDash(*sens, 8) : std::string("n/a"), d_sens})
                row.push_back(v);
            t.Add(row);
        }
    }
    out << t.str();
    out << "(every term by the shared evaluator, at steady state: dT/dt 0, supply 5 V, between\n"
           " heating and cooling and between directions, warmed up; temperatures outside a set's\n"
           " valid range are extrapolated; n/a: the stored model is not usable)\n";
    return out.str();
}

nlohmann::json HistoryJson(const std::string& sensor_id, const std::vector<db::CoeffSetInfo>& sets,
                           const std::vector<double>& ref_temps_c) {
    nlohmann::json j;
    j["sensor_id"] = sensor_id;
    j["ref_temps_c"] = ref_temps_c;
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& s : sets) {
        nlohmann::json e = CoeffSetJson(s);
        if (!s.station.empty()) e["station"] = s.station;
        nlohmann::json at = nlohmann::json::array();
        for (double temp : ref_temps_c) {
            const auto off = Eval(s.set.offset, temp);
            const auto sens = Eval(s.set.sensitivity, temp);
            at.push_back(
                {{"temp_c", temp},
                 {"offset_v", off ? JsonNumber(*off) : nlohmann::json(nullptr)},
                 {"sensitivity_v_per_dps", sens ? JsonNumber(*sens) : nlohmann::json(nullptr)}});
        }
        e["at_ref_temps"] = at;
        arr.push_back(e);
    }
    j["coeff_sets"] = arr;
    return j;
}

}  // namespace gyrocal::format
