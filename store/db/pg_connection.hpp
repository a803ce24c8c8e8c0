#pragma once
// A libpqxx connection to the central database, with its failures turned into one-line
// CentralErrors that never carry the password. Used by the central backend, the schema and the
// push; only their .cpp files include it (libpqxx stays out of the store's public headers).
#include <memory>
#include <pqxx/pqxx>
#include <string>

#include "store/db/central_db.hpp"

namespace gyrocal::db {

class CentralConnection {
public:
    // Connects (libpq reads the password from the URL, PGPASSFILE or PGPASSWORD; TLS as the URL's
    // sslmode says, "prefer" by default: encrypted whenever the server offers it). A connect
    // timeout of 10 s is added unless the URL or PGCONNECT_TIMEOUT sets one.
    explicit CentralConnection(const std::string& url);

    pqxx::connection& conn() { return *conn_; }
    const std::string& url() const { return url_; }
    const std::string& name() const { return name_; }  // URL without credentials

    // `e` (from libpqxx, libpq or the server) as a CentralError: "central database 'NAME': WHAT:
    // the server's message" on one line, the password redacted.
    [[noreturn]] void Fail(const std::exception& e, const std::string& what) const;

private:
    std::string url_, name_;
    std::unique_ptr<pqxx::connection> conn_;
};

// One line from a multi-line server message ("FATAL:  ...\n\tIs the server running ...").
std::string OneLine(const std::string& message);

// The schema version of the connected database (gyrocal_meta 'schema_version'), 0 when it has no
// gyrocal schema; -1 when it holds tables but none of gyrocal's (not a gyrocal database).
int CentralSchemaVersion(pqxx::transaction_base& tx);

}  // namespace gyrocal::db
