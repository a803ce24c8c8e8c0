#include "store/db/pg_connection.hpp"

#include <cstdlib>

#include "store/db/central_url.hpp"

namespace gyrocal::db {
namespace {

// The URL with a connect timeout, unless it or the environment already sets one: an unreachable
// host must be a clear error within seconds, not a hang.
std::string WithConnectTimeout(const std::string& url) {
    if (url.find("connect_timeout=") != std::string::npos || std::getenv("PGCONNECT_TIMEOUT"))
        return url;
    return url + (url.find('?') == std::string::npos ? "?" : "&") + "connect_timeout=10";
}

}  // namespace

std::string OneLine(const std::string& message) {
    std::string out;
    for (char c : message) {
        const bool space = c == '\n' || c == '\t' || c == '\r' || c == ' ';
        if (space && (out.empty() || out.back() == ' ')) continue;
        out += space ? ' ' : c;
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    for (const char* noise : {"FATAL: ", "ERROR: "}) {
        for (size_t at = out.find(noise); at != std::string::npos; at = out.find(noise))
            out.erase(at, std::string(noise).size());
    }
    return out;
}

CentralConnection::CentralConnection(const std::string& url)
    : url_(url), name_(WithoutCredentials(url)) {
    try {
        conn_ = std::make_unique<pqxx::connection>(WithConnectTimeout(url));
    } catch (const std::exception& e) {
        throw CentralError("cannot connect to central database '" + name_ +
                               "': " + RedactCredentials(OneLine(e.what()), url_),
                           "", true);
    }
}

void CentralConnection::Fail(const std::exception& e, const std::string& what) const {
    std::string state;
    bool lost = dynamic_cast<const pqxx::broken_connection*>(&e) != nullptr;
    if (const auto* sql = dynamic_cast<const pqxx::sql_error*>(&e)) state = sql->sqlstate();
    // Class 08: connection exceptions; 57P01-03: the server shut down or restarts.
    if (state.rfind("08", 0) == 0 || state.rfind("57P0", 0) == 0) lost = true;
    if (conn_ && !conn_->is_open()) lost = true;
    std::string msg = RedactCredentials(OneLine(e.what()), url_);
    if (const size_t query = msg.find(" Query was: "); query != std::string::npos)
        msg.erase(query);  // libpqxx repeats the whole statement
    std::string hint;
    if (state == "42501")
        hint = " (the role needs the grants of gyrocal central grant: store/README.md)";
    throw CentralError("central database '" + name_ + "': " + (lost ? "connection lost: " : "") +
                           what + ": " + msg + hint,
                       state, lost);
}

int CentralSchemaVersion(pqxx::transaction_base& tx) {
    const pqxx::result meta = tx.exec("SELECT to_regclass('gyrocal_meta') IS NOT NULL");
    if (!meta[0][0].as<bool>()) {
        const pqxx::result tables = tx.exec(
            "SELECT count(*) FROM pg_catalog.pg_class c JOIN pg_catalog.pg_namespace n ON "
            "n.oid = c.relnamespace WHERE n.nspname = current_schema() AND c.relkind IN "
            "('r', 'v', 'p')");
        return tables[0][0].as<int64_t>() > 0 ? -1 : 0;
    }
    const pqxx::result app = tx.exec("SELECT value FROM gyrocal_meta WHERE key = 'application'");
    if (app.empty() || app[0][0].as<std::string>() != "gyrocal") return -1;
    const pqxx::result v = tx.exec("SELECT value FROM gyrocal_meta WHERE key = 'schema_version'");
    return v.empty() ? 0 : std::atoi(v[0][0].c_str());
}

}  // namespace gyrocal::db
