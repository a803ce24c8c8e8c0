#pragma once
// A thin RAII layer over the SQLite C API: one connection (Db) and prepared statements (Stmt)
// with bound parameters only. Every failure throws StoreError whose what() names the database
// file and the SQL that failed, so callers can print one clear line.
//
// The same Db and Stmt also run the store's queries on a central PostgreSQL database (a Db made
// by ConnectCentral, central_db.hpp): the query code is written once, in the SQL both engines
// agree on (bound parameters as ?N, CAST(? AS TEXT) where a parameter is only tested for NULL,
// an alias on every subquery in FROM), and the engine behind a Db is a DbBackend (db_backend.hpp).
// A Db opened on a file has no backend object: SQLite is called directly, as before.
#include <sqlite3.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace gyrocal::db {

class StoreError : public std::runtime_error {
public:
    explicit StoreError(const std::string& what, int sqlite_code = 0, int os_errno = 0)
        : std::runtime_error(what), sqlite_code_(sqlite_code), os_errno_(os_errno) {}
    // SQLite's extended result code of the failure (e.g. SQLITE_FULL, SQLITE_IOERR_WRITE); 0 when
    // the error is not SQLite's (bad input, a file that is not a gyrocal database...).
    int sqlite_code() const { return sqlite_code_; }
    // The OS error behind an I/O or open failure (errno), 0 when none.
    int os_errno() const { return os_errno_; }

private:
    int sqlite_code_ = 0;
    int os_errno_ = 0;
};

// A failure of the storage under the database rather than of the data or the file's contents:
// the disk is full, the file or its file system became read-only, another writer holds the lock,
// or an I/O error. Writing the same rows again can succeed once that is fixed.
bool IsStorageFault(int sqlite_code);
// What an operator should hear: "disk full", "read-only", "file removed or replaced", "locked by
// another writer", "I/O error", "cannot open"; "" for any other code. An I/O error whose OS
// error says read-only (EROFS, EPERM: e.g. an immutable file, EACCES) is "read-only", and one
// that says no space (ENOSPC, EDQUOT) is "disk full".
std::string StorageFaultName(int sqlite_code, int os_errno = 0);
std::string StorageFaultName(const StoreError& e);

class Stmt;
class DbBackend;
class StmtBackend;

class Db {
public:
    enum class Mode { kReadWriteCreate, kReadWrite, kReadOnly };
    // Opens `path`; throws StoreError naming the path when it cannot.
    Db(const std::string& path, Mode mode);
    // A connection through another engine (the central PostgreSQL database); `name` is what
    // messages call it (a URL without its credentials).
    Db(std::string name, std::unique_ptr<DbBackend> backend);
    Db(const Db&) = delete;
    Db& operator=(const Db&) = delete;
    ~Db();

    void Exec(std::string_view sql);  // one or more statements, no parameters
    Stmt Prepare(std::string_view sql);
    int64_t LastInsertRowId() const;  // SQLite only
    int UserVersion();
    void SetUserVersion(int version);  // SQLite only
    // The file, or for a central database its URL without credentials (safe to print).
    const std::string& path() const { return path_; }
    sqlite3* raw() const { return db_; }  // nullptr for a central database
    // The engine behind a central database; nullptr for an SQLite file.
    DbBackend* backend() const { return backend_.get(); }
    // Throws StoreError: "database 'PATH': WHAT: SQLite's message" with the extended code, and the
    // OS error behind an I/O, disk-full or open failure.
    [[noreturn]] void Fail(std::string_view what) const;
    void SetBusyTimeout(int ms);
    // True when the file at path() is no longer the one this connection has open (removed,
    // renamed or replaced): writes would go to a file nobody can read any more.
    bool HasMoved() const;

private:
    std::string path_;
    sqlite3* db_ = nullptr;
    std::unique_ptr<DbBackend> backend_;
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
    Stmt& Bind(int i, const std::optional<std::string>& v) { return v ? Bind(i, *v) : BindNull(i); }

    // Binds `values` to parameters first, first + 1, ... in order, each as Bind does.
    template <class... Values>
    Stmt& BindFrom(int first, const Values&... values) {
        int i = first;
        (Bind(i++, values), ...);
        return *this;
    }
    // The same from parameter 1.
    template <class... Values>
    Stmt& BindAll(const Values&... values) {
        return BindFrom(1, values...);
    }

    bool Step();
    void Run() {
        Step();
        Reset();
    }  // for INSERT/UPDATE
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
    // Reads columns first, first + 1, ... into `fields` in order, each by its type: std::string
    // (Text), int64_t (Int), int32_t (Int, narrowed), double (Real), bool (Int != 0),
    // std::optional<int64_t> and std::optional<double> (NULL as nullopt).
    template <class... Fields>
    void Read(int first, Fields&... fields) const {
        int col = first;
        (ReadInto(col++, fields), ...);
    }

private:
    void ReadInto(int col, std::string& v) const { v = Text(col); }
    void ReadInto(int col, int64_t& v) const { v = Int(col); }
    void ReadInto(int col, int32_t& v) const { v = static_cast<int32_t>(Int(col)); }
    void ReadInto(int col, double& v) const { v = Real(col); }
    void ReadInto(int col, bool& v) const { v = Int(col) != 0; }
    void ReadInto(int col, std::optional<int64_t>& v) const { v = OptInt(col); }
    void ReadInto(int col, std::optional<double>& v) const { v = OptReal(col); }

    Db* db_;
    sqlite3_stmt* stmt_ = nullptr;
    std::string sql_;
    std::unique_ptr<StmtBackend> be_;  // set for a central database, instead of stmt_
};

// The rows `sql` selects with `key` bound to ?1, each made by read_row(stmt), in order.
template <class Key, class ReadRow>
auto SelectAll(Db& db, std::string_view sql, const Key& key, ReadRow read_row) {
    Stmt s(db, sql);
    s.Bind(1, key);
    std::vector<std::decay_t<std::invoke_result_t<ReadRow&, const Stmt&>>> out;
    while (s.Step()) out.push_back(read_row(s));
    return out;
}

// BEGIN IMMEDIATE ... COMMIT, rolled back when destroyed without Commit() (on a central database:
// BEGIN ... COMMIT).
class Transaction {
public:
    explicit Transaction(Db& db);
    ~Transaction();
    void Commit();

private:
    Db& db_;
    bool done_ = false;
};

}  // namespace gyrocal::db
