#pragma once
// The seam between the store's SQL and an engine other than SQLite (the central PostgreSQL
// database, pg_backend.cpp). A Db with a backend hands every statement to it; the query code
// above (query.cpp, fit_query.cpp, analyses.cpp, replay_reader.cpp, ...) is the same for both.
//
// Contract, as SQLite's: parameters are 1-based and written ?N or ? in the SQL (the backend
// translates them), NaN is bound as NULL, a NULL read as a real is NaN, Step() returns true while
// rows are available, Reset() makes the statement reusable with new bindings. Failures throw
// StoreError naming the database (without credentials) and the statement.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::db {

// The start of a statement on one line (whitespace runs collapsed, cut at 100 characters with
// "..."): how a failure of either engine names its statement.
std::string Snippet(std::string_view sql);

class StmtBackend {
public:
    virtual ~StmtBackend() = default;
    virtual void BindText(int i, std::string_view v) = 0;
    virtual void BindInt(int i, int64_t v) = 0;
    virtual void BindReal(int i, double v) = 0;  // NaN never reaches here (bound as NULL)
    virtual void BindBlob(int i, const void* data, int size) = 0;
    virtual void BindNull(int i) = 0;
    virtual bool Step() = 0;
    virtual void Reset() = 0;
    virtual bool IsNull(int col) const = 0;
    virtual int64_t Int(int col) const = 0;  // NULL reads as 0, a boolean as 0/1
    virtual double Real(int col) const = 0;  // NULL reads as NaN
    virtual std::string Text(int col) const = 0;
    virtual std::vector<uint8_t> Blob(int col) const = 0;
    virtual int ColumnCount() const = 0;
    virtual std::string ColumnName(int col) const = 0;
};

class DbBackend {
public:
    virtual ~DbBackend() = default;
    virtual std::unique_ptr<StmtBackend> Prepare(std::string_view sql) = 0;
    virtual void Exec(std::string_view sql) = 0;  // one or more statements, no parameters
    virtual int SchemaVersion() = 0;              // 0: no gyrocal schema
    virtual void Begin() = 0;
    virtual void Commit() = 0;
    virtual void Rollback() = 0;
};

}  // namespace gyrocal::db
