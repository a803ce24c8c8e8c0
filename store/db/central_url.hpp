#pragma once
// Names of central databases: a PostgreSQL URL (postgresql://[user[:password]@][host][:port]/db
// [?param=value&...], libpq's URI syntax) wherever a command takes --db FILE.
//
// Credentials come from the URL, from a password file (PGPASSFILE, or ~/.pgpass) or from the
// environment (PGUSER, PGPASSWORD, ...), as libpq reads them. They are never printed: every
// message, stored command line and run configuration carries the URL through
// WithoutCredentials, and error text from the server through RedactCredentials.
#include <string>

namespace gyrocal::db {

// True for "postgresql://..." and "postgres://..." (what libpq takes as a URI).
bool IsCentralUrl(const std::string& s);

// The URL with its password (user:PASSWORD@, and any password=... parameter) replaced by "***".
// Anything that is not a central URL is returned as it is.
std::string WithoutCredentials(const std::string& s);

// `text` with every occurrence of the password that `url` carries (as written and percent-
// decoded) replaced by "***", for messages that quote a server or library error.
std::string RedactCredentials(const std::string& text, const std::string& url);

// Every central URL inside a command line or JSON text made safe to store or print: each
// postgresql://... token is passed through WithoutCredentials.
std::string WithoutCredentialsIn(const std::string& text);

}  // namespace gyrocal::db
