// The central schema (store/db/central_schema.cpp) on a real PostgreSQL server: the station
// schema's steps translated, so every table has the station's columns (and the rowid SQLite keeps
// implicitly) and every view answers as on the station file; an older centre migrates step by
// step; a database holding other tables is refused untouched; two `central init` at once.
#include <gtest/gtest.h>

#include <set>
#include <thread>

#include "store/db/central_db.hpp"
#include "store/db/push.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "tests/store/pg_server.hpp"
#include "tests/store/scratch_db.hpp"
#include "tests/store/station_fixture.hpp"

namespace gyrocal::testing {
namespace {

namespace st = gyrocal::db;

// name -> its columns, in order (tables and views), from either engine through the query layer.
std::map<std::string, std::vector<std::string>> Columns(st::Db& db, bool central) {
    std::map<std::string, std::vector<std::string>> out;
    st::Stmt s(db, central
                       ? "SELECT table_name, column_name FROM information_schema.columns "
                         "WHERE table_schema = current_schema() ORDER BY table_name, "
                         "ordinal_position"
                       : "SELECT m.name, p.name FROM sqlite_master m, pragma_table_info(m.name) p "
                         "WHERE m.type IN ('table', 'view') ORDER BY m.name, p.cid");
    while (s.Step()) out[s.Text(0)].push_back(s.Text(1));
    return out;
}

TEST(CentralSchema, EveryTableAndViewHasTheStationsColumns) {
    PgServer& server = SharedPgServer();
    const std::string url = server.Url(server.NewDatabase("schema"));
    EXPECT_EQ(st::InitCentral(url), 0);
    EXPECT_EQ(st::InitCentral(url), st::kSchemaVersion);  // a second init changes nothing
    const std::string path = FreshDbPath("central_schema_station");
    WriteStation(path, {.prefix = "V", .runs = 1, .samples_per_sensor = 10});
    auto station = st::OpenForQuery(path);
    auto centre = st::OpenForQuery(url);
    const auto mine = Columns(*station, false);
    const auto there = Columns(*centre, true);
    for (const auto& [name, cols] : mine) {
        ASSERT_TRUE(there.count(name)) << name;
        std::vector<std::string> theirs = there.at(name);
        // The centre's rowid column (explicit where SQLite's is implicit), and g.* in a view.
        theirs.erase(std::remove(theirs.begin(), theirs.end(), "rowid"), theirs.end());
        EXPECT_EQ(theirs, cols) << name;
    }
}

TEST(CentralSchema, TheViewsAnswerAsOnTheStationsFile) {
    PgServer& server = SharedPgServer();
    const std::string url = server.Url(server.NewDatabase("views"));
    st::InitCentral(url);
    const std::string path = FreshDbPath("central_views_station");
    WriteStation(path, {.prefix = "W", .runs = 2, .samples_per_sensor = 200});
    st::PushOptions o;
    o.station_db = path;
    o.central_url = url;
    ASSERT_EQ(st::Push(o).failed(), 0);
    auto station = st::OpenForQuery(path);
    auto centre = st::OpenForQuery(url);
    // Each view's rows as text, ids as the station's (modulo 10^12), in a fixed order.
    const std::vector<std::pair<std::string, std::string>> views = {
        {"v_run_summary",
         "SELECT run_id, outcome, gyro_samples, plateaus, sensitivity_points, "
         "coeff_sets, seq_gaps, queue_drops FROM v_run_summary ORDER BY run_id"},
        {"v_latest_coeffs",
         "SELECT sensor_id, run_id, coeff_set_id, source, offset_terms, "
         "offset_t0_c, sensitivity_terms FROM v_latest_coeffs ORDER BY 1"},
        {"v_coeff_provenance",
         "SELECT coeff_row_id % 1000000000000, kind, item_id, n_samples, "
         "item_found FROM v_coeff_provenance ORDER BY 1, 2, 3"},
        {"v_coeff_samples", "SELECT count(*), sum(seq) FROM v_coeff_samples"},
        {"v_analyses",
         "SELECT analysis_id % 1000000000000, outcome, added_effects, created_utc "
         "FROM v_analyses ORDER BY 1"},
        {"v_fit_final",
         "SELECT run_id, sensor_id, status, excluded FROM v_fit_final ORDER BY 1, 2"},
        {"v_noise", "SELECT run_id, sensor_id, arw_dps_rthz FROM v_noise ORDER BY 1, 2"},
        {"v_repeatability", "SELECT run_id, sensor_id, verdict FROM v_repeatability ORDER BY 1, 2"},
    };
    for (const auto& [name, sql] : views) {
        auto rows = [&](st::Db& db) {
            std::vector<std::string> out;
            st::Stmt s(db, sql);
            while (s.Step()) {
                std::string line;
                for (int i = 0; i < s.ColumnCount(); ++i) {
                    // Numbers compared by value (engines print reals differently), text as is;
                    // a boolean (PostgreSQL) as the 0/1 SQLite gives.
                    std::string t = s.Text(i);
                    const bool number =
                        !t.empty() && t.find_first_not_of("0123456789.-+eE") == std::string::npos;
                    if (t.rfind("analysis:", 0) == 0)  // an id: the station's is the last digits
                        t = "analysis:" +
                            std::to_string(std::stoll(t.substr(9)) % st::kRunKeyScale);
                    line += (t == "t" || t == "f") ? std::to_string(static_cast<double>(s.Int(i)))
                            : number               ? std::to_string(s.Real(i))
                                                   : t;
                    line += "|";
                }
                out.push_back(line);
            }
            return out;
        };
        const auto a = rows(*station), b = rows(*centre);
        EXPECT_FALSE(a.empty()) << name;
        EXPECT_EQ(b, a) << name;
    }
}

TEST(CentralSchema, AnOlderCentreIsMigratedStepByStep) {
    PgServer& server = SharedPgServer();
    const std::string name = server.NewDatabase("older");
    // The centre as gyrocal with schema 6 left it.
    for (int v = 0; v < 6; ++v) server.Sql(name, st::CentralStep(v));
    server.Sql(name, "INSERT INTO gyrocal_meta(key, value) VALUES ('schema_version', '6')");
    EXPECT_THROW(st::OpenForQuery(server.Url(name)), st::StoreError);  // read: migrate it first
    EXPECT_EQ(st::InitCentral(server.Url(name)), 6);
    EXPECT_EQ(server.Query(name, "SELECT value FROM gyrocal_meta WHERE key = 'schema_version'"),
              std::to_string(st::kSchemaVersion));
    EXPECT_NO_THROW(st::OpenForQuery(server.Url(name)));
}

TEST(CentralSchema, ADatabaseWithOtherTablesIsRefusedAndLeftAlone) {
    PgServer& server = SharedPgServer();
    const std::string name = server.NewDatabase("foreign");
    server.Sql(name, "CREATE TABLE invoices (id int)");
    try {
        st::InitCentral(server.Url(name));
        ADD_FAILURE() << "a foreign database was initialised";
    } catch (const st::StoreError& e) {
        EXPECT_NE(std::string(e.what()).find("is not a gyrocal database"), std::string::npos);
    }
    EXPECT_EQ(server.Query(name, "SELECT count(*) FROM pg_tables WHERE schemaname = 'public'"),
              "1");
}

TEST(CentralSchema, TwoInitsAtOnceMakeOneSchema) {
    PgServer& server = SharedPgServer();
    const std::string url = server.Url(server.NewDatabase("race"));
    std::string errors[2];
    std::thread a([&] {
        try {
            st::InitCentral(url);
        } catch (const std::exception& e) {
            errors[0] = e.what();
        }
    });
    std::thread b([&] {
        try {
            st::InitCentral(url);
        } catch (const std::exception& e) {
            errors[1] = e.what();
        }
    });
    a.join();
    b.join();
    EXPECT_EQ(errors[0], "");
    EXPECT_EQ(errors[1], "");
    EXPECT_NO_THROW(st::OpenForQuery(url));
}

}  // namespace
}  // namespace gyrocal::testing
