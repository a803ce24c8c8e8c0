#pragma once
// The central PostgreSQL database of a lab: every station's runs, pushed from the stations'
// SQLite files (push.hpp). Its schema is the station schema (schema.cpp), translated statement by
// statement to PostgreSQL and migrated the same way (central_schema.cpp), so the query library
// (query.hpp) reads it through the same Db and Stmt as a file.
//
// Ids at the centre: a pushed run gets a run_key (run_origins); every row of that run keeps its
// station row id plus run_key * kRunKeyScale (coeff_row_id, plateau_row_id, analysis_id, ..., and
// the rowid column every central table has where SQLite has an implicit one). The station's own
// id is the last 12 digits; ids of different stations' runs never meet.
#include <cstdint>
#include <memory>
#include <string>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

inline constexpr int64_t kRunKeyScale = 1'000'000'000'000;  // 10^12 station rows per run key

// A failure that came from the central database or the way to it. `sqlstate` is PostgreSQL's
// error code ("" when the connection itself failed); `connection` is true when the connection
// could not be made or was lost (a push can be tried again later).
class CentralError : public StoreError {
public:
    CentralError(const std::string& what, std::string sqlstate, bool connection)
        : StoreError(what), sqlstate_(std::move(sqlstate)), connection_(connection) {}
    const std::string& sqlstate() const { return sqlstate_; }
    bool connection() const { return connection_; }

private:
    std::string sqlstate_;
    bool connection_;
};

// Connects to the central database at `url` for reading, in one read-only snapshot (repeatable
// read) for the life of the Db, and checks that it is a gyrocal database of this software's
// schema version. Throws CentralError: unreachable, refused credentials, not a gyrocal database,
// an older schema (migrate it: gyrocal central init) or a newer one.
std::unique_ptr<Db> OpenCentralForQuery(const std::string& url);

// The schema version of the central database at `url` (0: no gyrocal schema), and what it holds,
// for `gyrocal central status`.
struct CentralStatus {
    std::string name;  // URL without credentials
    int schema_version = 0;
    std::string server_version;
    int64_t runs = 0, stations = 0;
    bool ssl = false;  // the connection is encrypted (TLS)
};
CentralStatus ReadCentralStatus(const std::string& url);

// Creates the gyrocal schema in the (empty) central database at `url`, or migrates an older one to
// this software's version, step by step, one transaction each, under an advisory lock so that two
// at once do not collide. Needs the rights of the database's owner. Throws CentralError when the
// database holds other tables and no gyrocal schema, or is newer than this software. Returns the
// version it found.
int InitCentral(const std::string& url);

// Grants `role` what `gyrocal push` needs (INSERT and SELECT on gyrocal's tables, USAGE on their
// id sequences; with `updates`, also UPDATE on runs and losses, which pushing runs that are still
// open needs) or, with `read_only`, SELECT only. Owner's rights needed.
void GrantCentral(const std::string& url, const std::string& role, bool read_only, bool updates);

// The PostgreSQL text of the schema step from `from_version` (the station's step, translated).
std::string CentralStep(int from_version);

// The SQL of `sql` with SQLite's ?N and ? parameters written as PostgreSQL's $N (string literals,
// quoted names and comments left alone).
std::string ToDollarParams(const std::string& sql);

}  // namespace gyrocal::db
