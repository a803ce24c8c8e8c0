#pragma once
// Minimal read-only SQL for the end-to-end checks (the store's own library is tested in
// tests/store): rows as text, one integer or real.
#include <sqlite3.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocal {

class Sql {
public:
    explicit Sql(const std::string& path) {
        if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
            throw std::runtime_error("cannot open " + path);
        sqlite3_busy_timeout(db_, 5000);
    }
    ~Sql() { sqlite3_close(db_); }
    Sql(const Sql&) = delete;
    Sql& operator=(const Sql&) = delete;
    std::vector<std::vector<std::string>> Rows(const std::string& sql) {
        sqlite3_stmt* st = nullptr;
        if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK)
            throw std::runtime_error(std::string("bad SQL: ") + sqlite3_errmsg(db_) + ": " + sql);
        std::vector<std::vector<std::string>> out;
        while (sqlite3_step(st) == SQLITE_ROW) {
            std::vector<std::string> row;
            for (int i = 0; i < sqlite3_column_count(st); ++i) {
                const unsigned char* t = sqlite3_column_text(st, i);
                row.push_back(t ? reinterpret_cast<const char*>(t) : "");
            }
            out.push_back(row);
        }
        sqlite3_finalize(st);
        return out;
    }
    int64_t Int(const std::string& sql) { return std::stoll(Rows(sql).at(0).at(0)); }
    double Real(const std::string& sql) { return std::stod(Rows(sql).at(0).at(0)); }
    // ATTACH another file read-only under `name`, to compare two databases in one query.
    void Attach(const std::string& path, const std::string& name) {
        Rows("ATTACH '" + path + "' AS " + name);
    }

private:
    sqlite3* db_ = nullptr;
};

}  // namespace gyrocal
