#pragma once
// A thin RAII layer over the SQLite C API: one connection (Db) and prepared statements (Stmt)
// with bound parameters only. Every failure throws StoreError whose what() names the database
// file and the SQL that failed, so callers can print one clear line.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::store {

class StoreError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Stmt;

class Db {
public:
    enum class Mode { kReadWriteCreate, kReadWrite, kReadOnly };
    // Opens `path`; throws StoreError naming the path when it cannot.
    Db(const std::string& path, Mode mode);
    Db(const Db&) = delete;
    Db& operator=(const Db&) = delete;
    ~Db();

    void Exec(std::string_view sql);  // one or more statements, no parameters
    Stmt Prepare(std::string_view sql);
    int64_t LastInsertRowId() const;
    int UserVersion();
    void SetUserVersion(int version);
    const std::string& path() const { return path_; }
    sqlite3* raw() const { return db_; }
    [[noreturn]] void Fail(std::string_view what) const;

private:
    std::string path_;
    sqlite3* db_ = nullptr;
};

// A prepared statement. Bind indexes are 1-based as in SQLite. Step() returns true while rows
// are available; Reset() makes it reusable with new bindings.
class Stmt {
public:
    Stmt(Db& db, std::string_view sql);
    Stmt(Stmt&& other) noexcept;
    Stmt& operator=(Stmt&&) = delete;
    Stmt(const Stmt&) = delete;
    ~Stmt();

    Stmt& Bind(int i, int64_t v);
    Stmt& Bind(int i, int v) { return Bind(i, static_cast<int64_t>(v)); }
    Stmt& Bind(int i, double v);  // NaN is stored as NULL (SQLite has no NaN)
    Stmt& Bind(int i, std::string_view v);
    Stmt& Bind(int i, const char* v) { return Bind(i, std::string_view(v)); }
    Stmt& Bind(int i, const std::string& v) { return Bind(i, std::string_view(v)); }
    Stmt& BindBlob(int i, const void* data, int size);
    Stmt& BindNull(int i);
    Stmt& Bind(int i, std::optional<double> v) { return v ? Bind(i, *v) : BindNull(i); }
    Stmt& Bind(int i, std::optional<int64_t> v) { return v ? Bind(i, *v) : BindNull(i); }

    bool Step();
    void Run() { Step(); Reset(); }  // for INSERT/UPDATE
    void Reset();

    bool IsNull(int col) const;
    int64_t Int(int col) const;
    double Real(int col) const;  // NULL reads as NaN
    std::string Text(int col) const;
    std::vector<uint8_t> Blob(int col) const;
    std::optional<double> OptReal(int col) const;
    std::optional<int64_t> OptInt(int col) const;
    int ColumnCount() const;
    std::string ColumnName(int col) const;

private:
    Db* db_;
    sqlite3_stmt* stmt_ = nullptr;
    std::string sql_;
};

// BEGIN IMMEDIATE ... COMMIT, rolled back when destroyed without Commit().
class Transaction {
public:
    explicit Transaction(Db& db);
    ~Transaction();
    void Commit();

private:
    Db& db_;
    bool done_ = false;
};

}  // namespace gyrocal::store
