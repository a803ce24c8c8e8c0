// The central schema: the station schema's steps (schema.cpp), each translated to PostgreSQL
// when it runs, so that the two cannot drift apart. What the translation does:
//   - types: INTEGER -> BIGINT (SQLite's integers are 64-bit), REAL -> DOUBLE PRECISION,
//     BLOB -> BYTEA, TEXT -> TEXT COLLATE "C" (sorted byte by byte, as SQLite sorts); an INTEGER
//     PRIMARY KEY (SQLite's row id) becomes an identity column;
//   - every table gets the `rowid` column SQLite gives it implicitly (the query code orders by
//     it, and gyro_blocks points into gyro_samples by it): an identity column, indexed, or for a
//     table with an INTEGER PRIMARY KEY a generated copy of that key;
//   - the few SQLite functions the views and migrations use (group_concat, json_group_array,
//     printf('%.Ng'), json_valid, json_extract, json_type, json_each, datetime) are defined in
//     PostgreSQL under the same names before the first step (kCompat);
//   - where a statement is written in a way PostgreSQL refuses (a subquery in FROM without an
//     alias), a patch for that step replaces the exact text (kPatches): it must be found, so a
//     changed station step fails the central migration test instead of drifting silently.
#include <regex>
#include <string>
#include <vector>

#include "store/db/central_db.hpp"
#include "store/db/pg_connection.hpp"
#include "store/db/schema.hpp"

namespace gyrocal::db {
namespace {

constexpr const char* kCompat = R"sql(
CREATE FUNCTION gyrocal_concat(acc text, v text, sep text) RETURNS text LANGUAGE sql IMMUTABLE
  AS $$ SELECT CASE WHEN v IS NULL THEN acc WHEN acc IS NULL THEN v ELSE acc || sep || v END $$;
CREATE FUNCTION gyrocal_concat(acc text, v text) RETURNS text LANGUAGE sql IMMUTABLE
  AS $$ SELECT gyrocal_concat(acc, v, ',') $$;
CREATE AGGREGATE group_concat(text, text) (SFUNC = gyrocal_concat, STYPE = text);
CREATE AGGREGATE group_concat(text) (SFUNC = gyrocal_concat, STYPE = text);
CREATE FUNCTION gyrocal_json_array(a text[]) RETURNS text LANGUAGE sql IMMUTABLE
  AS $$ SELECT array_to_json(a)::text $$;
CREATE AGGREGATE json_group_array(text) (SFUNC = array_append, STYPE = text[],
  FINALFUNC = gyrocal_json_array, INITCOND = '{}');
-- SQLite's printf for the one form the views use, %.Ng (C's %g with N significant digits).
CREATE FUNCTION printf(fmt text, v double precision) RETURNS text LANGUAGE plpgsql IMMUTABLE AS $$
DECLARE p int; e int; m text; x numeric;
BEGIN
  p := substring(fmt from '^%\.([0-9]+)g$')::int;
  IF p IS NULL THEN RAISE EXCEPTION 'printf: only %%.Ng is defined here, not %', fmt; END IF;
  IF v IS NULL THEN RETURN ''; END IF;
  IF v = 0 THEN RETURN '0'; END IF;
  IF v = 'NaN'::float8 THEN RETURN 'NaN'; END IF;
  IF v = 'Infinity'::float8 THEN RETURN 'Inf'; END IF;
  IF v = '-Infinity'::float8 THEN RETURN '-Inf'; END IF;
  m := trim(to_char(abs(v), '9.' || repeat('0', greatest(p - 1, 1)) || 'EEEE'));
  e := substring(m from 'e([-+][0-9]+)$')::int;
  IF e < -4 OR e >= p THEN
    m := rtrim(rtrim(substring(m from '^[0-9.]+'), '0'), '.');
    RETURN CASE WHEN v < 0 THEN '-' ELSE '' END || m || 'e' ||
           CASE WHEN e < 0 THEN '-' ELSE '+' END || lpad(abs(e)::text, 2, '0');
  END IF;
  x := round(v::numeric, p - 1 - e);
  m := x::text;
  IF position('.' in m) > 0 THEN m := rtrim(rtrim(m, '0'), '.'); END IF;
  RETURN m;
END $$;
CREATE FUNCTION json_valid(t text) RETURNS boolean LANGUAGE plpgsql IMMUTABLE AS $$
BEGIN
  PERFORM t::jsonb;
  RETURN t IS NOT NULL;
EXCEPTION WHEN others THEN
  RETURN false;
END $$;
CREATE FUNCTION gyrocal_json_path(path text) RETURNS text[] LANGUAGE sql IMMUTABLE
  AS $$ SELECT CASE WHEN path = '$' THEN ARRAY[]::text[]
                    ELSE string_to_array(substr(path, 3), '.') END $$;
CREATE FUNCTION json_extract(t text, path text) RETURNS text LANGUAGE sql IMMUTABLE
  AS $$ SELECT (t::jsonb) #>> gyrocal_json_path(path) $$;
CREATE FUNCTION json_type(t text, path text) RETURNS text LANGUAGE sql IMMUTABLE AS $$
  SELECT CASE jsonb_typeof(j) WHEN 'string' THEN 'text' WHEN 'boolean' THEN j::text
    WHEN 'number' THEN CASE WHEN j::text ~ '^-?[0-9]+$' THEN 'integer' ELSE 'real' END
    ELSE jsonb_typeof(j) END
  FROM (SELECT (t::jsonb) #> gyrocal_json_path(path) AS j) AS x $$;
CREATE FUNCTION json_each(t text) RETURNS TABLE (key text, value text) LANGUAGE sql IMMUTABLE
  AS $$ SELECT (o - 1)::text, e::text FROM jsonb_array_elements(
          CASE WHEN jsonb_typeof(t::jsonb) = 'array' THEN t::jsonb ELSE '[]'::jsonb END)
          WITH ORDINALITY AS a(e, o)
        UNION ALL
        SELECT k, v::text FROM jsonb_each(
          CASE WHEN jsonb_typeof(t::jsonb) = 'object' THEN t::jsonb ELSE '{}'::jsonb END)
          AS b(k, v) $$;
CREATE FUNCTION datetime(seconds bigint, modifier text) RETURNS text LANGUAGE sql IMMUTABLE
  AS $$ SELECT to_char(to_timestamp(seconds) AT TIME ZONE 'UTC', 'YYYY-MM-DD HH24:MI:SS') $$;
)sql";

struct Patch {
    int from_version;  // the step it applies to (version from -> from + 1)
    const char* find;
    const char* replace;
};

// Subqueries in FROM need an alias in PostgreSQL 15 (SQLite and PostgreSQL 16 do without).
constexpr Patch kPatches[] = {
    {1, "AND t.role = 'offset'\n      ORDER BY term_index))",
     "AND t.role = 'offset'\n      ORDER BY term_index) AS ordered_terms)"},
    {1, "AND t.role = 'sensitivity' ORDER BY term_index))",
     "AND t.role = 'sensitivity' ORDER BY term_index) AS ordered_terms)"},
};

// `sql` with -- comments removed (outside literals): they may hold parentheses.
std::string WithoutComments(const std::string& sql) {
    std::string out;
    for (size_t i = 0; i < sql.size(); ++i) {
        if (sql[i] == '\'') {
            const size_t end = sql.find('\'', i + 1);
            const size_t stop = end == std::string::npos ? sql.size() : end + 1;
            out.append(sql, i, stop - i);
            i = stop - 1;
        } else if (sql[i] == '-' && i + 1 < sql.size() && sql[i + 1] == '-') {
            i = std::min(sql.find('\n', i), sql.size()) - 1;
        } else {
            out += sql[i];
        }
    }
    return out;
}

// Adds the rowid column to every CREATE TABLE of `sql` (types already translated).
std::string WithRowids(const std::string& sql) {
    static const std::regex kCreate(R"(CREATE TABLE (\w+) \()");
    static const std::regex kIdKey(R"((\w+) BIGINT GENERATED BY DEFAULT AS IDENTITY PRIMARY KEY)");
    std::string out;
    size_t pos = 0;
    std::smatch m;
    auto begin = sql.cbegin();
    while (std::regex_search(begin + static_cast<long>(pos), sql.cend(), m, kCreate)) {
        const size_t open = pos + static_cast<size_t>(m.position(0) + m.length(0)) - 1;
        int depth = 0;
        size_t close = open;
        for (; close < sql.size(); ++close) {
            if (sql[close] == '(') ++depth;
            if (sql[close] == ')' && --depth == 0) break;
        }
        const std::string body = sql.substr(open + 1, close - open - 1);
        std::smatch key;
        std::string rowid;
        if (std::regex_search(body, key, kIdKey)) {
            rowid = "rowid BIGINT GENERATED ALWAYS AS (" + key[1].str() + ") STORED";
        } else if (body.find("PRIMARY KEY") != std::string::npos) {
            rowid = "rowid BIGINT GENERATED BY DEFAULT AS IDENTITY UNIQUE";
        } else {
            rowid = "rowid BIGINT GENERATED BY DEFAULT AS IDENTITY PRIMARY KEY";
        }
        out.append(sql, pos, close - pos);
        out += ",\n  " + rowid;
        pos = close;
    }
    out.append(sql, pos, std::string::npos);
    return out;
}

}  // namespace

// Declared for the tests (central_schema_test): the PostgreSQL text of step `from_version`.
std::string CentralStep(int from_version) {
    std::string sql(SchemaStep(from_version));
    for (const Patch& p : kPatches) {
        if (p.from_version != from_version) continue;
        const size_t at = sql.find(p.find);
        if (at == std::string::npos) {
            throw StoreError("central schema: the patch for step " + std::to_string(from_version) +
                             " no longer matches (find '" + p.find +
                             "'): update kPatches in central_schema.cpp");
        }
        sql.replace(at, std::string(p.find).size(), p.replace);
    }
    sql = WithoutComments(sql);
    sql = std::regex_replace(sql, std::regex(R"(\bINTEGER PRIMARY KEY\b)"),
                             "BIGINT GENERATED BY DEFAULT AS IDENTITY PRIMARY KEY");
    sql = std::regex_replace(sql, std::regex(R"(\bINTEGER\b)"), "BIGINT");
    sql = std::regex_replace(sql, std::regex(R"(\bREAL\b)"), "DOUBLE PRECISION");
    sql = std::regex_replace(sql, std::regex(R"(\bBLOB\b)"), "BYTEA");
    // Text compares and sorts byte by byte, as SQLite's BINARY does, whatever the database's
    // default collation (a lab's server may well be created with en_US.UTF-8).
    sql = std::regex_replace(sql, std::regex(R"(\bTEXT\b)"), "TEXT COLLATE \"C\"");
    sql = WithRowids(sql);
    return from_version == 0 ? std::string(kCompat) + sql : sql;
}

int InitCentral(const std::string& url) {
    CentralConnection c(url);
    int found = -2;
    for (;;) {
        int version = 0;
        try {
            pqxx::work tx(c.conn());
            // One migrator at a time; the version is read again under the lock.
            tx.exec("SELECT pg_advisory_xact_lock(hashtext('gyrocal schema'))");
            version = CentralSchemaVersion(tx);
            if (found == -2) found = version;
            if (version < 0) {
                throw CentralError("central database '" + c.name() +
                                       "' is not a gyrocal database (it holds other tables and "
                                       "no gyrocal_meta): use an empty database",
                                   "", false);
            }
            if (version > kSchemaVersion) {
                throw CentralError("central database '" + c.name() + "' has schema version " +
                                       std::to_string(version) + ", newer than this software (" +
                                       std::to_string(kSchemaVersion) + ")",
                                   "", false);
            }
            if (version == kSchemaVersion) return found;
            tx.exec(CentralStep(version));
            tx.exec_params(
                "INSERT INTO gyrocal_meta(key, value) VALUES ('schema_version', $1) "
                "ON CONFLICT (key) DO UPDATE SET value = EXCLUDED.value",
                std::to_string(version + 1));
            tx.commit();
        } catch (const CentralError&) {
            throw;
        } catch (const std::exception& e) {
            c.Fail(e, "migrating from schema version " + std::to_string(version));
        }
    }
}

void GrantCentral(const std::string& url, const std::string& role, bool read_only, bool updates) {
    CentralConnection c(url);
    try {
        pqxx::work tx(c.conn());
        const std::string who = tx.quote_name(role);
        tx.exec("GRANT SELECT" + std::string(read_only ? "" : ", INSERT") +
                " ON ALL TABLES IN SCHEMA " +
                tx.quote_name(tx.exec("SELECT current_schema()")[0][0].c_str()) + " TO " + who);
        if (updates && !read_only) tx.exec("GRANT UPDATE ON runs, losses TO " + who);
        tx.commit();
    } catch (const std::exception& e) {
        c.Fail(e, "granting to role '" + role + "'");
    }
}

CentralStatus ReadCentralStatus(const std::string& url) {
    CentralConnection c(url);
    CentralStatus s;
    s.name = c.name();
    try {
        pqxx::work tx(c.conn());
        s.schema_version = CentralSchemaVersion(tx);
        s.server_version = tx.exec("SHOW server_version")[0][0].c_str();
        s.ssl = tx.exec(
                      "SELECT coalesce((SELECT ssl FROM pg_stat_ssl WHERE pid = "
                      "pg_backend_pid()), false)")[0][0]
                    .as<bool>();
        if (s.schema_version >= 9) {
            const auto r = tx.exec(
                "SELECT count(*), count(DISTINCT station_host || ':' || station_db) FROM "
                "run_origins");
            s.runs = r[0][0].as<int64_t>();
            s.stations = r[0][1].as<int64_t>();
        }
    } catch (const std::exception& e) {
        c.Fail(e, "reading its status");
    }
    return s;
}

}  // namespace gyrocal::db
