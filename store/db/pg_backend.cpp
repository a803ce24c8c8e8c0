// The central database behind a Db: a libpqxx connection with one transaction at a time;
// statements over sample tables are read through server-side cursors (a run's millions of
// samples never sit in memory at once), the others in one round trip. Readers work in one read-only
// REPEATABLE READ snapshot for the life of the Db, so a push that commits meanwhile does not change
// the answer half-way.
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "store/db/central_url.hpp"
#include "store/db/db_backend.hpp"
#include "store/db/pg_connection.hpp"
#include "store/db/schema.hpp"

namespace gyrocal::db {
namespace {

// True for a statement that may return a run's worth of rows: it reads a table of samples (the
// replay reader, the sample export, the analysis' loader). It is read through a server-side
// cursor, 20 000 rows at a time; any other statement in one round trip (a history over a
// thousand runs is a few thousand statements: three round trips each would triple its time).
bool ReadsSamples(const std::string& sql) {
    for (const char* table : {"gyro_samples", "encoder_samples", "chamber_states", "rates",
                              "power_states", "plateau_states", "raw_events", "status"}) {
        if (sql.find(std::string("FROM ") + table) != std::string::npos) return true;
    }
    return false;
}

// True for a statement that returns rows.
bool IsQuery(const std::string& sql) {
    size_t i = sql.find_first_not_of(" \t\r\n(");
    if (i == std::string::npos) return false;
    std::string word;
    while (i < sql.size() && std::isalpha(static_cast<unsigned char>(sql[i])))
        word += static_cast<char>(std::toupper(static_cast<unsigned char>(sql[i++])));
    return word == "SELECT" || word == "WITH" || word == "VALUES";
}

// Highest $N in a translated statement.
int MaxParam(const std::string& sql) {
    int max = 0;
    for (size_t i = 0; i + 1 < sql.size(); ++i) {
        if (sql[i] == '$' && std::isdigit(static_cast<unsigned char>(sql[i + 1])))
            max = std::max(max, std::atoi(sql.c_str() + i + 1));
    }
    return max;
}

class PgBackend;

class PgStmt final : public StmtBackend {
public:
    PgStmt(PgBackend& be, std::string sql);
    ~PgStmt() override;
    void BindText(int i, std::string_view v) override { Set(i, std::string(v)); }
    void BindInt(int i, int64_t v) override { Set(i, std::to_string(v)); }
    void BindReal(int i, double v) override;
    void BindBlob(int i, const void* data, int size) override;
    void BindNull(int i) override { Set(i, std::nullopt); }
    bool Step() override;
    void Reset() override;
    bool IsNull(int col) const override { return Field(col).is_null(); }
    int64_t Int(int col) const override;
    double Real(int col) const override;
    std::string Text(int col) const override;
    std::vector<uint8_t> Blob(int col) const override;
    int ColumnCount() const override { return static_cast<int>(rows_.columns()); }
    std::string ColumnName(int col) const override { return rows_.column_name(col); }

private:
    void Set(int i, std::optional<std::string> v);
    void Start();
    void Fetch();
    void Close();
    pqxx::field Field(int col) const {
        return rows_[static_cast<pqxx::result::size_type>(cur_)][col];
    }

    PgBackend& be_;
    std::string sql_;
    bool query_;
    std::vector<std::optional<std::string>> params_;
    pqxx::result rows_;
    size_t next_ = 0, cur_ = 0;
    bool started_ = false, done_ = false, open_ = false;
    std::string cursor_;
    uint64_t generation_ = 0;
    int fetch_rows_ = 500;
};

class PgBackend final : public DbBackend {
public:
    explicit PgBackend(std::unique_ptr<CentralConnection> c) : c_(std::move(c)) {}
    ~PgBackend() override {
        try {
            if (tx_) tx_->abort();
        } catch (...) {
        }
    }
    std::unique_ptr<StmtBackend> Prepare(std::string_view sql) override {
        return std::make_unique<PgStmt>(*this, ToDollarParams(std::string(sql)));
    }
    void Exec(std::string_view sql) override {
        try {
            Tx().exec(std::string(sql));
        } catch (const std::exception& e) {
            c_->Fail(e, "'" + Snippet(sql) + "'");
        }
    }
    int SchemaVersion() override {
        try {
            return CentralSchemaVersion(Tx());
        } catch (const CentralError&) {
            throw;
        } catch (const std::exception& e) {
            c_->Fail(e, "reading its schema version");
        }
    }
    void Begin() override {
        End(true);
        tx_ = std::make_unique<pqxx::work>(c_->conn());
    }
    void Commit() override { End(true); }
    void Rollback() override { End(false); }

    // The open transaction; a read-only snapshot is opened when there is none.
    pqxx::transaction_base& Tx() {
        if (!tx_) {
            tx_ = std::make_unique<pqxx::transaction<pqxx::repeatable_read, pqxx::read_only>>(
                c_->conn());
        }
        return *tx_;
    }
    uint64_t generation() const { return generation_; }
    std::string NextCursor() { return "gyrocal_c" + std::to_string(++cursors_); }
    const CentralConnection& connection() const { return *c_; }

private:
    void End(bool commit) {
        if (!tx_) return;
        auto tx = std::move(tx_);
        ++generation_;
        try {
            if (commit) {
                tx->commit();
            } else {
                tx->abort();
            }
        } catch (const std::exception& e) {
            c_->Fail(e, commit ? "commit" : "rollback");
        }
    }

    std::unique_ptr<CentralConnection> c_;
    std::unique_ptr<pqxx::transaction_base> tx_;
    uint64_t generation_ = 0, cursors_ = 0;
};

PgStmt::PgStmt(PgBackend& be, std::string sql)
    : be_(be), sql_(std::move(sql)), query_(IsQuery(sql_)) {
    params_.resize(static_cast<size_t>(MaxParam(sql_)));
}

PgStmt::~PgStmt() {
    try {
        Close();
    } catch (...) {  // the transaction is gone or failed: its cursors went with it
    }
}

void PgStmt::Set(int i, std::optional<std::string> v) {
    if (i < 1) throw StoreError("central database: parameter index " + std::to_string(i));
    if (static_cast<size_t>(i) > params_.size()) params_.resize(static_cast<size_t>(i));
    params_[static_cast<size_t>(i - 1)] = std::move(v);
}

void PgStmt::BindReal(int i, double v) {
    if (std::isinf(v)) return Set(i, v > 0 ? "Infinity" : "-Infinity");
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back exact
    Set(i, std::string(buf, r.ptr));
}

void PgStmt::BindBlob(int i, const void* data, int size) {
    static const char* kHex = "0123456789abcdef";
    std::string s = "\\x";
    const auto* p = static_cast<const unsigned char*>(data);
    for (int k = 0; k < size; ++k) {
        s += kHex[p[k] >> 4];
        s += kHex[p[k] & 15];
    }
    Set(i, std::move(s));
}

void PgStmt::Start() {
    std::vector<const char*> values;
    for (const auto& p : params_) values.push_back(p ? p->c_str() : nullptr);
    const auto params = pqxx::prepare::make_dynamic_params(values);
    try {
        pqxx::transaction_base& tx = be_.Tx();
        if (!query_ || !ReadsSamples(sql_)) {
            rows_ = tx.exec_params(sql_, params);
            done_ = true;
        } else {
            cursor_ = be_.NextCursor();
            tx.exec_params("DECLARE " + cursor_ + " NO SCROLL CURSOR FOR " + sql_, params);
            open_ = true;
            generation_ = be_.generation();
            rows_ = pqxx::result();
        }
    } catch (const CentralError&) {
        throw;
    } catch (const std::exception& e) {
        be_.connection().Fail(e, "query '" + Snippet(sql_) + "'");
    }
    started_ = true;
    next_ = 0;
}

void PgStmt::Fetch() {
    try {
        rows_ = be_.Tx().exec("FETCH " + std::to_string(fetch_rows_) + " FROM " + cursor_);
    } catch (const std::exception& e) {
        be_.connection().Fail(e, "query '" + Snippet(sql_) + "'");
    }
    next_ = 0;
    if (rows_.size() < static_cast<size_t>(fetch_rows_)) {
        done_ = true;
        Close();
    }
    fetch_rows_ = 20000;  // a long result: larger batches
}

void PgStmt::Close() {
    if (open_ && generation_ == be_.generation()) be_.Tx().exec("CLOSE " + cursor_);
    open_ = false;
}

bool PgStmt::Step() {
    if (!started_) Start();
    for (;;) {
        if (next_ < rows_.size()) {
            cur_ = next_++;
            return true;
        }
        if (done_) return false;
        Fetch();
    }
}

void PgStmt::Reset() {
    Close();
    started_ = done_ = false;
    rows_ = pqxx::result();
    next_ = cur_ = 0;
    fetch_rows_ = 500;
    std::fill(params_.begin(), params_.end(), std::nullopt);
}

int64_t PgStmt::Int(int col) const {
    const pqxx::field f = Field(col);
    if (f.is_null()) return 0;
    const char* s = f.c_str();
    if (s[0] == 't' && s[1] == '\0') return 1;  // a boolean (e.g. a view's "x IS NOT NULL")
    if (s[0] == 'f' && s[1] == '\0') return 0;
    char* end = nullptr;
    const long long v = std::strtoll(s, &end, 10);
    if (end != s && *end == '\0') return v;
    return std::llround(std::strtod(s, nullptr));  // numeric with a fraction (e.g. an average)
}

double PgStmt::Real(int col) const {
    const pqxx::field f = Field(col);
    if (f.is_null()) return std::nan("");
    return std::strtod(f.c_str(), nullptr);  // also reads NaN, Infinity, -Infinity
}

std::string PgStmt::Text(int col) const {
    const pqxx::field f = Field(col);
    if (f.is_null()) return {};
    return std::string(f.c_str(), f.size());
}

std::vector<uint8_t> PgStmt::Blob(int col) const {
    const pqxx::field f = Field(col);
    std::vector<uint8_t> out;
    if (f.is_null()) return out;
    const std::string s(f.c_str(), f.size());
    if (s.rfind("\\x", 0) != 0) return std::vector<uint8_t>(s.begin(), s.end());
    for (size_t i = 2; i + 1 < s.size(); i += 2)
        out.push_back(static_cast<uint8_t>(std::stoi(s.substr(i, 2), nullptr, 16)));
    return out;
}

}  // namespace

std::string ToDollarParams(const std::string& sql) {
    std::string out;
    out.reserve(sql.size() + 16);
    int highest = 0;
    for (size_t i = 0; i < sql.size(); ++i) {
        const char c = sql[i];
        if (c == '\'' || c == '"') {  // a literal or a quoted name, copied whole
            const size_t end = sql.find(c, i + 1);
            const size_t stop = end == std::string::npos ? sql.size() : end + 1;
            out.append(sql, i, stop - i);
            i = stop - 1;
        } else if (c == '-' && i + 1 < sql.size() && sql[i + 1] == '-') {
            const size_t end = sql.find('\n', i);
            const size_t stop = end == std::string::npos ? sql.size() : end;
            out.append(sql, i, stop - i);
            i = stop - 1;
        } else if (c == '?') {
            size_t j = i + 1;
            while (j < sql.size() && std::isdigit(static_cast<unsigned char>(sql[j]))) ++j;
            // SQLite: ?N is parameter N; a bare ? is one more than the highest so far.
            const int n = j > i + 1 ? std::atoi(sql.c_str() + i + 1) : highest + 1;
            highest = std::max(highest, n);
            out += "$" + std::to_string(n);
            i = j - 1;
        } else {
            out += c;
        }
    }
    return out;
}

std::unique_ptr<Db> OpenCentralForQuery(const std::string& url) {
    auto c = std::make_unique<CentralConnection>(url);
    const std::string name = c->name();
    auto backend = std::make_unique<PgBackend>(std::move(c));
    const int version = backend->SchemaVersion();
    if (version < 0) {
        throw CentralError("central database '" + name +
                               "' is not a gyrocal database (it holds other tables and no "
                               "gyrocal_meta)",
                           "", false);
    }
    if (version == 0) {
        throw CentralError("central database '" + name +
                               "' has no gyrocal schema yet (create it: gyrocal central init "
                               "--db URL, as the database's owner)",
                           "", false);
    }
    if (version > kSchemaVersion) {
        throw CentralError("central database '" + name + "' has schema version " +
                               std::to_string(version) + ", newer than this software (" +
                               std::to_string(kSchemaVersion) + "): use a newer gyrocal",
                           "", false);
    }
    if (version < kSchemaVersion) {
        throw CentralError("central database '" + name + "' has schema version " +
                               std::to_string(version) + ", older than this software (" +
                               std::to_string(kSchemaVersion) +
                               "): migrate it with gyrocal central init --db URL, as its owner",
                           "", false);
    }
    return std::make_unique<Db>(name, std::move(backend));
}

}  // namespace gyrocal::db
