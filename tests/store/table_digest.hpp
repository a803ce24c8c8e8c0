#pragma once
// Row counts and a checksum per table of one run, read through the store's own Db/Stmt from a
// station's SQLite file or from the central database alike, so that "the centre holds exactly the
// station's rows" is one comparison. Written apart from the push (its own selection of a run's
// rows, its own reading of ids) so that it checks the push rather than repeating it.
//
// Ids: the centre keeps a station's row id plus run_key * 10^12 (store/db/central_db.hpp); the
// digest reads every id column modulo 10^12 on both sides (a station's ids are far below it), and
// an 'analysis:<id>' source likewise. Reals are hashed by their exact value (both engines store
// IEEE doubles), text and blobs byte for byte, NULL as its own token.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "store/db/central_db.hpp"
#include "store/db/push_tables.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::testing {

struct TableDigest {
    int64_t rows = 0;
    uint64_t hash = 1469598103934665603ULL;  // FNV-1a 64
    bool operator==(const TableDigest& o) const { return rows == o.rows && hash == o.hash; }
};

inline void Mix(TableDigest& d, const std::string& s) {
    for (unsigned char c : s) {
        d.hash ^= c;
        d.hash *= 1099511628211ULL;
    }
    d.hash ^= 0xff;  // field separator
    d.hash *= 1099511628211ULL;
}

// Columns that hold row ids (the push moves them by run_key * 10^12).
inline bool IsIdColumn(const std::string& c) {
    static const std::set<std::string> ids = {
        "coeff_row_id", "plateau_row_id",    "rotation_row_id", "analysis_id", "validation_id",
        "noise_row_id", "fit_report_row_id", "first_rowid",     "last_rowid",  "push_id"};
    return ids.count(c) > 0;
}

// The run's rows of `table`, as the test reads them: by run_id, or through the parent table.
inline std::string RunRowsWhere(const std::string& table) {
    if (table == "coeff_models" || table == "coeff_terms" || table == "coeff_covariance" ||
        table == "coeff_set_plateaus" || table == "coeff_set_rotations")
        return "coeff_row_id IN (SELECT coeff_row_id FROM coeff_sets WHERE run_id = ?1)";
    if (table == "noise_adev")
        return "noise_row_id IN (SELECT noise_row_id FROM noise_estimates WHERE run_id = ?1)";
    if (table == "fit_exclusions")
        return "fit_report_row_id IN (SELECT fit_report_row_id FROM fit_reports WHERE run_id = ?1)";
    if (table == "sensors")
        return "sensor_id IN (SELECT sensor_id FROM run_sensors WHERE run_id = ?1)";
    return "run_id = ?1";
}

// Every pushed table's digest for `run_id`; the column lists come from the station file.
inline std::map<std::string, TableDigest> RunDigests(db::Db& db, db::Db& station,
                                                     const std::string& run_id) {
    std::map<std::string, TableDigest> out;
    for (const db::push::Table& t : db::push::StationTables(station)) {
        if (t.scope == db::push::Scope::kLocal) continue;
        std::string cols, order;
        for (const auto& c : t.columns) cols += (cols.empty() ? "" : ", ") + c.name;
        // Station order: by row id, which the centre keeps (offset) in `rowid` or the key.
        const std::string id = t.id_is_key ? t.id_column : "rowid";
        db::Stmt s(db, "SELECT " + cols + " FROM " + t.name + " WHERE " + RunRowsWhere(t.name) +
                           " ORDER BY " + id);
        s.Bind(1, run_id);
        TableDigest& d = out[t.name];
        while (s.Step()) {
            ++d.rows;
            for (size_t i = 0; i < t.columns.size(); ++i) {
                const int col = static_cast<int>(i);
                const auto& c = t.columns[i];
                if (s.IsNull(col)) {
                    Mix(d, "\x01NULL");
                } else if (IsIdColumn(c.name)) {
                    Mix(d, std::to_string(s.Int(col) % db::kRunKeyScale));
                } else if (c.kind == 'i') {
                    Mix(d, std::to_string(s.Int(col)));
                } else if (c.kind == 'r') {
                    const double v = s.Real(col);
                    Mix(d, std::string(reinterpret_cast<const char*>(&v), sizeof v));
                } else if (c.kind == 'b') {
                    const auto b = s.Blob(col);
                    Mix(d, std::string(b.begin(), b.end()));
                } else {
                    std::string v = s.Text(col);
                    if (c.name == "source" && v.rfind("analysis:", 0) == 0)
                        v = "analysis:" +
                            std::to_string(std::stoll(v.substr(9)) % db::kRunKeyScale);
                    Mix(d, v);
                }
            }
        }
    }
    return out;
}

}  // namespace gyrocal::testing
