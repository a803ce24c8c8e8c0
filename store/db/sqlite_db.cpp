#include "store/db/sqlite_db.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

#include "store/db/db_backend.hpp"

namespace gyrocal::db {

bool IsStorageFault(int code) {
    switch (code & 0xff) {
        case SQLITE_FULL:
        case SQLITE_READONLY:
        case SQLITE_BUSY:
        case SQLITE_LOCKED:
        case SQLITE_IOERR:
        case SQLITE_CANTOPEN:
        case SQLITE_PROTOCOL:
            return true;
        default:
            return false;
    }
}

std::string Snippet(std::string_view sql) {
    std::string out;
    for (char c : sql) {
        const bool space = c == ' ' || c == '\n' || c == '\t' || c == '\r';
        if (space && (out.empty() || out.back() == ' ')) continue;
        out += space ? ' ' : c;
        if (out.size() >= 100) return out + "...";
    }
    return out;
}

std::string StorageFaultName(const StoreError& e) {
    return StorageFaultName(e.sqlite_code(), e.os_errno());
}

std::string StorageFaultName(int code, int os_errno) {
    if ((code & 0xff) == SQLITE_IOERR) {
        if (os_errno == EROFS || os_errno == EPERM || os_errno == EACCES) return "read-only";
        if (os_errno == ENOSPC || os_errno == EDQUOT) return "disk full";
    }
    switch (code & 0xff) {
        case SQLITE_FULL:
            return "disk full";
        case SQLITE_READONLY:
            return code == SQLITE_READONLY_DBMOVED ? "file removed or replaced" : "read-only";
        case SQLITE_BUSY:
        case SQLITE_LOCKED:
        case SQLITE_PROTOCOL:
            return "locked by another writer";
        case SQLITE_IOERR:
            return "I/O error";
        case SQLITE_CANTOPEN:
            return "cannot open";
        default:
            return "";
    }
}

namespace {
// SQLite's message, with the OS error behind it when there is one (e.g. "disk I/O error (OS:
// Operation not permitted)" for a write to a file made immutable).
std::string Describe(sqlite3* db) {
    std::string msg = sqlite3_errmsg(db);
    const int primary = sqlite3_extended_errcode(db) & 0xff;
    const int os = sqlite3_system_errno(db);
    if (os != 0 &&
        (primary == SQLITE_IOERR || primary == SQLITE_FULL || primary == SQLITE_CANTOPEN)) {
        msg += std::string(" (OS: ") + std::strerror(os) + ")";
    }
    return msg;
}
// "database 'PATH': " or, when the file itself is the problem, "database 'PATH' is damaged
// (...)" so that the cause comes before the statement that met it.
std::string Prefix(const std::string& path, int code) {
    if ((code & 0xff) == SQLITE_CORRUPT) return "database '" + path + "' is damaged: ";
    if ((code & 0xff) == SQLITE_NOTADB) return "'" + path + "' is not an SQLite database: ";
    return "database '" + path + "': ";
}
}  // namespace

Db::Db(const std::string& path, Mode mode) : path_(path) {
    int flags = SQLITE_OPEN_NOMUTEX;
    switch (mode) {
        case Mode::kReadWriteCreate:
            flags |= SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
            break;
        case Mode::kReadWrite:
            flags |= SQLITE_OPEN_READWRITE;
            break;
        case Mode::kReadOnly:
            flags |= SQLITE_OPEN_READONLY;
            break;
    }
    const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
    if (rc != SQLITE_OK) {
        std::string msg = db_ ? Describe(db_) : sqlite3_errstr(rc);
        const int code = db_ ? sqlite3_extended_errcode(db_) : rc;
        const int os = db_ ? sqlite3_system_errno(db_) : 0;
        sqlite3_close(db_);
        db_ = nullptr;
        throw StoreError("cannot open database '" + path + "': " + msg, code, os);
    }
    sqlite3_extended_result_codes(db_, 1);
    // Concurrent readers (query tools) and the recorder's writer may meet: wait, do not fail.
    sqlite3_busy_timeout(db_, 5000);
}

Db::Db(std::string name, std::unique_ptr<DbBackend> backend)
    : path_(std::move(name)), backend_(std::move(backend)) {}

Db::~Db() {
    if (db_ != nullptr) sqlite3_close_v2(db_);
}

void Db::Fail(std::string_view what) const {
    const int code = sqlite3_extended_errcode(db_);
    throw StoreError(Prefix(path_, code) + std::string(what) + ": " + Describe(db_), code,
                     sqlite3_system_errno(db_));
}

void Db::SetBusyTimeout(int ms) {
    if (db_ != nullptr) sqlite3_busy_timeout(db_, ms);
}

bool Db::HasMoved() const {
    if (db_ == nullptr) return false;
    int moved = 0;
    return sqlite3_file_control(db_, "main", SQLITE_FCNTL_HAS_MOVED, &moved) == SQLITE_OK &&
           moved != 0;
}

void Db::Exec(std::string_view sql) {
    if (backend_) return backend_->Exec(sql);
    const std::string s(sql);
    if (sqlite3_exec(db_, s.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK) {
        const int code = sqlite3_extended_errcode(db_);
        throw StoreError(Prefix(path_, code) + Describe(db_) + " (in: " + Snippet(s) + ")", code,
                         sqlite3_system_errno(db_));
    }
}

Stmt Db::Prepare(std::string_view sql) { return Stmt(*this, sql); }

int64_t Db::LastInsertRowId() const {
    if (backend_) throw StoreError("database '" + path_ + "': no row ids here (SQLite only)");
    return sqlite3_last_insert_rowid(db_);
}

int Db::UserVersion() {
    if (backend_) return backend_->SchemaVersion();
    Stmt s(*this, "PRAGMA user_version");
    s.Step();
    return static_cast<int>(s.Int(0));
}

void Db::SetUserVersion(int version) {
    if (backend_) throw StoreError("database '" + path_ + "': its version is set by its migration");
    Exec("PRAGMA user_version = " + std::to_string(version));
}

Stmt::Stmt(Db& db, std::string_view sql) : db_(&db), sql_(sql) {
    if (db.backend() != nullptr) {
        be_ = db.backend()->Prepare(sql_);
        return;
    }
    if (sqlite3_prepare_v2(db.raw(), sql_.c_str(), static_cast<int>(sql_.size()), &stmt_,
                           nullptr) != SQLITE_OK) {
        db.Fail("cannot prepare '" + Snippet(sql_) + "'");
    }
}

Stmt::Stmt(Stmt&& other) noexcept
    : db_(other.db_), stmt_(other.stmt_), sql_(std::move(other.sql_)), be_(std::move(other.be_)) {
    other.stmt_ = nullptr;
}

Stmt::~Stmt() { sqlite3_finalize(stmt_); }

// Each operation below goes to the backend when the database has one (a central database),
// else to SQLite.
Stmt& Stmt::Bind(int i, int64_t v) {
    if (be_) return be_->BindInt(i, v), *this;
    if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) db_->Fail("bind");
    return *this;
}
Stmt& Stmt::Bind(int i, double v) {
    if (std::isnan(v)) return BindNull(i);
    if (be_) return be_->BindReal(i, v), *this;
    if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) db_->Fail("bind");
    return *this;
}
Stmt& Stmt::Bind(int i, std::string_view v) {
    if (be_) return be_->BindText(i, v), *this;
    if (sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT) !=
        SQLITE_OK) {
        db_->Fail("bind");
    }
    return *this;
}
Stmt& Stmt::BindBlob(int i, const void* data, int size) {
    if (be_) return be_->BindBlob(i, data, size), *this;
    if (sqlite3_bind_blob(stmt_, i, data, size, SQLITE_TRANSIENT) != SQLITE_OK) db_->Fail("bind");
    return *this;
}
Stmt& Stmt::BindNull(int i) {
    if (be_) return be_->BindNull(i), *this;
    if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) db_->Fail("bind");
    return *this;
}

bool Stmt::Step() {
    if (be_) return be_->Step();
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    const std::string msg = Describe(db_->raw());
    const int code = sqlite3_extended_errcode(db_->raw());
    const int os = sqlite3_system_errno(db_->raw());
    sqlite3_reset(stmt_);
    throw StoreError(Prefix(db_->path(), code) + msg + " (in: " + Snippet(sql_) + ")", code, os);
}

void Stmt::Reset() {
    if (be_) return be_->Reset();
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
}

bool Stmt::IsNull(int col) const {
    if (be_) return be_->IsNull(col);
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
}
int64_t Stmt::Int(int col) const {
    if (be_) return be_->Int(col);
    return sqlite3_column_int64(stmt_, col);
}
double Stmt::Real(int col) const {
    if (be_) return be_->Real(col);
    if (IsNull(col)) return std::numeric_limits<double>::quiet_NaN();
    return sqlite3_column_double(stmt_, col);
}
std::string Stmt::Text(int col) const {
    if (be_) return be_->Text(col);
    const auto* p = sqlite3_column_text(stmt_, col);
    if (p == nullptr) return {};
    return std::string(reinterpret_cast<const char*>(p),
                       static_cast<size_t>(sqlite3_column_bytes(stmt_, col)));
}
std::vector<uint8_t> Stmt::Blob(int col) const {
    if (be_) return be_->Blob(col);
    const auto* p = static_cast<const uint8_t*>(sqlite3_column_blob(stmt_, col));
    const int n = sqlite3_column_bytes(stmt_, col);
    if (p == nullptr || n <= 0) return {};
    return std::vector<uint8_t>(p, p + n);
}
std::optional<double> Stmt::OptReal(int col) const {
    if (IsNull(col)) return std::nullopt;
    return Real(col);
}
std::optional<int64_t> Stmt::OptInt(int col) const {
    if (IsNull(col)) return std::nullopt;
    return Int(col);
}
int Stmt::ColumnCount() const {
    if (be_) return be_->ColumnCount();
    return sqlite3_column_count(stmt_);
}
std::string Stmt::ColumnName(int col) const {
    if (be_) return be_->ColumnName(col);
    return sqlite3_column_name(stmt_, col);
}

Transaction::Transaction(Db& db) : db_(db) {
    if (db_.backend() != nullptr) {
        db_.backend()->Begin();
    } else {
        db_.Exec("BEGIN IMMEDIATE");
    }
}
Transaction::~Transaction() {
    if (!done_) {
        try {
            if (db_.backend() != nullptr) {
                db_.backend()->Rollback();
            } else {
                db_.Exec("ROLLBACK");
            }
        } catch (...) {
        }
    }
}
void Transaction::Commit() {
    if (db_.backend() != nullptr) {
        db_.backend()->Commit();
    } else {
        db_.Exec("COMMIT");
    }
    done_ = true;
}

}  // namespace gyrocal::db
