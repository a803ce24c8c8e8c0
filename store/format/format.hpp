#pragma once
// Formatting of query results for people (aligned tables) and scripts (JSON, CSV), and the C
// header that firmware includes. Pure: structs in, text out. Strings from the database are
// untrusted (they came off the network): tables replace control characters, CSV quotes, JSON
// escapes, and the C header turns ids into identifiers and never lets text end a comment.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "store/db/query.hpp"
#include "store/db/utc_text.hpp"

namespace gyrocal::format {

// "2026-11-21 05:14:00" (UTC) of a wall-clock utime [us]; "-" when absent.
using gyrocal::db::UtcText;
// Parses "YYYY-MM-DD" or "YYYY-MM-DD[T ]HH:MM[:SS][Z]" as UTC into utime [us]; nullopt if invalid.
std::optional<int64_t> ParseUtc(const std::string& text);
// Parses "0,25,50" into temperatures [degC]; nullopt when a value is not a finite number.
std::optional<std::vector<double>> ParseTemps(const std::string& text);

std::string RunsTable(const std::vector<db::RunInfo>& runs);
nlohmann::json RunsJson(const std::vector<db::RunInfo>& runs);

struct ProvenanceSummary {
    int64_t coeff_row_id = 0;
    std::vector<db::ProvenanceItem> items;
};
std::string RunDetailText(const db::RunDetail& d, const std::vector<ProvenanceSummary>& provenance);
nlohmann::json RunDetailJson(const db::RunDetail& d,
                             const std::vector<ProvenanceSummary>& provenance);

// How offset and sensitivity at the reference temperatures moved between coefficient sets.
std::string HistoryTable(const std::string& sensor_id, const std::vector<db::CoeffSetInfo>& sets,
                         const std::vector<double>& ref_temps_c);
nlohmann::json HistoryJson(const std::string& sensor_id, const std::vector<db::CoeffSetInfo>& sets,
                           const std::vector<double>& ref_temps_c);

nlohmann::json CoeffSetJson(const db::CoeffSetInfo& c);
std::string CoeffsCsv(const std::vector<db::CoeffSetInfo>& sets);
// `origin` is what the header says it was exported from (e.g. "run R1 of gyrocal.db").
// The header carries gyrocal_model.h verbatim (the input trackers, every registry term and the
// per-sample compensation), then each sensor's models and tracker configuration; a stored name
// the registry does not know evaluates to NAN.
std::string CoeffsCHeader(const std::vector<db::CoeffSetInfo>& sets, const std::string& origin);

// Replaces control characters (and DEL) by '?', for one-line display of untrusted text.
std::string Printable(const std::string& s);

}  // namespace gyrocal::format
