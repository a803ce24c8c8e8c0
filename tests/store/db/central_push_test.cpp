// The push to a lab's central PostgreSQL database (store/db/push.hpp) on a real throwaway server
// (tests/store/pg_server.hpp): exactly once, idempotent, deltas, open runs, three stations at
// once, the minimal role, and the refusals. "Equal" is checked per table: row count and a
// checksum of every value (tests/store/table_digest.hpp), read from both sides through the
// store's own query layer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "store/db/central_db.hpp"
#include "store/db/central_url.hpp"
#include "store/db/push.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "tests/store/pg_server.hpp"
#include "tests/store/scratch_db.hpp"
#include "tests/store/station_fixture.hpp"
#include "tests/store/table_digest.hpp"

namespace gyrocal::testing {
namespace {

namespace st = gyrocal::db;

std::string FileBytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// Every run of a station file (not the no-run bucket).
std::vector<std::string> StationRuns(const std::string& path) {
    auto db = st::OpenForQuery(path);
    std::vector<std::string> ids;
    for (const auto& r : st::ListRuns(*db, {}))
        if (!r.run_id.empty()) ids.push_back(r.run_id);
    return ids;
}

class CentralPush : public ::testing::Test {
protected:
    void SetUp() override {
        server_ = &SharedPgServer();
        db_name_ = server_->NewDatabase("push");
        url_ = server_->Url(db_name_);
        st::InitCentral(url_);
    }
    st::PushReport PushAll(const std::string& station, bool open = false,
                           const std::string& url = "") {
        st::PushOptions o;
        o.station_db = station;
        o.central_url = url.empty() ? url_ : url;
        o.include_open = open;
        o.software_version = "test";
        return st::Push(o);
    }
    // Every table of every run of `station` equal at the centre (sensors apart when `shared`).
    void ExpectCentreHolds(const std::string& station, bool shared_sensors = false) {
        auto s = st::OpenForQuery(station);
        auto c = st::OpenForQuery(url_);
        for (const std::string& run : StationRuns(station)) {
            auto mine = RunDigests(*s, *s, run);
            auto there = RunDigests(*c, *s, run);
            if (shared_sensors) mine.erase("sensors"), there.erase("sensors");
            for (const auto& [table, d] : mine) {
                EXPECT_EQ(there[table].rows, d.rows) << run << " " << table;
                EXPECT_EQ(there[table].hash, d.hash) << run << " " << table;
            }
        }
    }
    int64_t CentralCount(const std::string& table) {
        return std::stoll(server_->Query(db_name_, "SELECT count(*) FROM " + table));
    }
    PgServer* server_ = nullptr;
    std::string db_name_, url_;
};

TEST_F(CentralPush, EveryTableOfEveryRunArrivesExactlyAndASecondPushChangesNothing) {
    // GIVEN a station with two finished runs and rows in every table
    const std::string station = FreshDbPath("push_station_a");
    WriteStation(station, {.prefix = "A"});
    // WHEN it is pushed
    const st::PushReport first = PushAll(station);
    // THEN both runs are there, every table equal (count and checksum)
    ASSERT_EQ(first.runs.size(), 2u);
    for (const auto& r : first.runs) EXPECT_TRUE(r.ok) << r.error;
    EXPECT_EQ(first.runs[0].samples_added, 2 * 1500);
    ExpectCentreHolds(station);
    // AND pushing again (the run named, or what is new) adds nothing
    EXPECT_TRUE(st::RunsToPush(station, url_, false).empty());
    const int64_t samples = CentralCount("gyro_samples");
    st::PushOptions again;
    again.station_db = station;
    again.central_url = url_;
    again.run_ids = {"A-R1", "A-R2"};
    const st::PushReport second = st::Push(again);
    for (const auto& r : second.runs) {
        EXPECT_TRUE(r.ok);
        EXPECT_EQ(r.rows_added, 0) << r.run_id;
        EXPECT_EQ(r.rows_updated, 0) << r.run_id;
    }
    EXPECT_EQ(CentralCount("gyro_samples"), samples);
    ExpectCentreHolds(station);
    // AND the station recorded its pushes, without credentials
    auto s = st::OpenForQuery(station);
    EXPECT_EQ(Count(*s, "SELECT count(*) FROM pushes"), 4);
    EXPECT_EQ(Count(*s, "SELECT count(*) FROM pushes WHERE central LIKE '%" +
                            std::string(PgServer::kAdminPassword) + "%'"),
              0);
}

TEST_F(CentralPush, ARunThatGainedAnAnalysisSendsOnlyTheNewRows) {
    const std::string station = FreshDbPath("push_station_delta");
    WriteStation(station, {.prefix = "D", .runs = 1});
    PushAll(station);
    {  // a second analysis stored on the station after the push
        auto db = st::OpenForUpdate(station);
        AnalyseStationRun(*db, {.prefix = "D", .runs = 1}, 1, 7'000'000);
    }
    EXPECT_EQ(st::RunsToPush(station, url_, false), std::vector<std::string>{"D-R1"});
    const st::PushReport r = PushAll(station);
    ASSERT_EQ(r.runs.size(), 1u);
    // the analysis, its coefficient set and the set's models, terms and covariance
    EXPECT_EQ(r.runs[0].rows_added, 1 + 1 + 2 + (4 + 2) + (16 + 4));
    ExpectCentreHolds(station);
}

TEST_F(CentralPush, AnOpenRunIsPushedUpToWhatIsCommittedAndCompletedLater) {
    const std::string station = FreshDbPath("push_station_open");
    StationSpec spec{.prefix = "O", .runs = 1, .last_open = true};
    WriteStation(station, spec);
    // Without --include-open an open run is not new, and naming it is refused.
    EXPECT_TRUE(st::RunsToPush(station, url_, false).empty());
    st::PushOptions named;
    named.station_db = station;
    named.central_url = url_;
    named.run_ids = {"O-R1"};
    EXPECT_THROW(st::Push(named), st::StoreError);
    EXPECT_EQ(CentralCount("runs"), 1);  // only the no-run bucket
    ASSERT_TRUE(PushAll(station, true).runs.at(0).ok);
    EXPECT_EQ(server_->Query(db_name_, "SELECT outcome FROM runs WHERE run_id = 'O-R1'"),
              "running");
    // The recorder goes on: more losses, then the stop.
    {
        st::StoreWriter w(station, {"test", "O-host", 1});
        st::LossMap l;
        l[{"O-R1", ""}].queue_drops = 5;
        w.Write({RunEvent("O-R1", "stop", spec.sensors, spec.wall0_utime + 9'000'000'000)}, l);
    }
    const st::PushReport r = PushAll(station, false);
    ASSERT_EQ(r.runs.size(), 1u);
    EXPECT_TRUE(r.runs[0].ok) << r.runs[0].error;
    EXPECT_EQ(r.runs[0].rows_updated, 2);  // the run's row and one loss counter
    EXPECT_EQ(server_->Query(db_name_, "SELECT outcome FROM runs WHERE run_id = 'O-R1'"), "stop");
    ExpectCentreHolds(station);
}

TEST_F(CentralPush, ThreeStationsPushingAtOnceAreEachThereExactlyOnce) {
    // Three stations, the same units calibrated at each (history across stations), pushing
    // concurrently; station B pushes twice at once (two shells): the run lock keeps it once.
    std::vector<std::string> files;
    for (const char* p : {"A", "B", "C"}) {
        files.push_back(FreshDbPath(std::string("push_three_") + p));
        WriteStation(files.back(), {.prefix = p, .runs = 2, .samples_per_sensor = 3000});
    }
    std::vector<std::thread> threads;
    std::vector<st::PushReport> reports(4);
    std::vector<std::string> errors(4);
    for (size_t i = 0; i < 4; ++i) {
        threads.emplace_back([&, i] {
            try {
                reports[i] = PushAll(files[i == 3 ? 1 : i]);
            } catch (const std::exception& e) {
                errors[i] = e.what();
            }
        });
    }
    for (auto& t : threads) t.join();
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(errors[i], "");
        for (const auto& r : reports[i].runs) EXPECT_TRUE(r.ok) << r.error;
    }
    for (const auto& f : files) ExpectCentreHolds(f, true);
    EXPECT_EQ(CentralCount("run_origins"), 6);
    EXPECT_EQ(CentralCount("gyro_samples"), 3 * 2 * 2 * 3000);
    EXPECT_EQ(CentralCount("sensors"), 2);  // U01, U02: one row each for the whole lab
    // History across stations: every final set of U01, with its station.
    auto c = st::OpenForQuery(url_);
    const auto sets = st::SensorHistory(*c, "U01", true);
    std::set<std::string> stations, expected;
    for (const auto& s : sets) stations.insert(s.station.substr(s.station.find(':') + 1));
    for (const auto& f : files) expected.insert(std::filesystem::absolute(f).string());
    EXPECT_EQ(stations, expected);
}

TEST_F(CentralPush, ARoleWithOnlyInsertAndSelectPushesFinishedRuns) {
    server_->EnsureRole("gyro_pusher", "pusher-pw-1");
    st::GrantCentral(url_, "gyro_pusher", false, false);
    const std::string station = FreshDbPath("push_station_role");
    WriteStation(station, {.prefix = "P", .runs = 1, .last_open = false});
    const std::string as_pusher = server_->Url(db_name_, "gyro_pusher", "pusher-pw-1");
    const st::PushReport r = PushAll(station, false, as_pusher);
    ASSERT_EQ(r.runs.size(), 1u);
    EXPECT_TRUE(r.runs[0].ok) << r.runs[0].error;
    ExpectCentreHolds(station);
    // It cannot change what is there (no UPDATE, no DELETE), nor read the centre's other schemas.
    const std::string who = "gyro_pusher";
    EXPECT_EQ(
        server_->Query(db_name_, "SELECT has_table_privilege('" + who + "', 'runs', 'UPDATE')"),
        "f");
    EXPECT_EQ(server_->Query(db_name_, "SELECT has_table_privilege('" + who +
                                           "', 'gyro_samples', "
                                           "'DELETE')"),
              "f");
}

TEST_F(CentralPush, ARunIdThatIsAnotherRunAtTheCentreIsRefusedAndTheOthersGoOn) {
    const std::string a = FreshDbPath("push_same_id_a"), b = FreshDbPath("push_same_id_b");
    WriteStation(a, {.prefix = "S", .runs = 1});
    StationSpec other{.prefix = "S", .runs = 2};
    other.wall0_utime += 3600LL * 1000000LL * 24;  // S-R1 of another station: another start
    WriteStation(b, other);
    ASSERT_TRUE(PushAll(a).runs.at(0).ok);
    const int64_t samples = CentralCount("gyro_samples");
    const st::PushReport r = PushAll(b);
    ASSERT_EQ(r.runs.size(), 2u);
    EXPECT_FALSE(r.runs[0].ok);
    EXPECT_NE(r.runs[0].error.find("another run"), std::string::npos) << r.runs[0].error;
    EXPECT_TRUE(r.runs[1].ok) << r.runs[1].error;
    EXPECT_EQ(CentralCount("gyro_samples"), samples + 2 * 1500);
}

// What must be true after a refused push: one line naming the cause without the password, the
// station file byte for byte as before, the centre as it was.
class CentralRefusals : public CentralPush {
protected:
    void ExpectRefused(const std::function<void()>& push, const std::string& expected,
                       const std::string& station) {
        const std::string before = FileBytes(station);
        const int64_t runs = CentralCount("runs"), samples = CentralCount("gyro_samples");
        try {
            push();
            ADD_FAILURE() << "no error; expected: " << expected;
        } catch (const std::exception& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(expected), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
            EXPECT_EQ(what.find(PgServer::kAdminPassword), std::string::npos) << what;
            EXPECT_EQ(what.find("wrong-pw-3"), std::string::npos) << what;
        }
        EXPECT_EQ(FileBytes(station), before) << "the station file changed";
        EXPECT_EQ(CentralCount("runs"), runs);
        EXPECT_EQ(CentralCount("gyro_samples"), samples);
    }
    st::PushOptions Options(const std::string& station, const std::string& url) {
        st::PushOptions o;
        o.station_db = station;
        o.central_url = url;
        return o;
    }
};

TEST_F(CentralRefusals, EveryBadInputIsOneLineAndLeavesBothSidesAsTheyWere) {
    const std::string station = FreshDbPath("push_refused");
    WriteStation(station, {.prefix = "X", .runs = 1});
    auto o = Options(station, url_);
    {  // migrated to this version once (as any reader does), before the byte comparisons
        auto db = st::OpenForQuery(station);
    }
    // a run that does not exist
    o.run_ids = {"NOPE"};
    ExpectRefused([&] { st::Push(o); }, "no run 'NOPE'", station);
    o.run_ids = {};
    // an unreachable server (a socket folder where nothing listens)
    ExpectRefused([&] { st::Push(Options(station, "postgresql://x:y@/db?host=/nonexistent")); },
                  "cannot connect to central database", station);
    // wrong credentials
    ExpectRefused(
        [&] { st::Push(Options(station, server_->Url(db_name_, PgServer::kAdmin, "wrong-pw-3"))); },
        "password authentication failed", station);
    // a database that is not gyrocal's
    const std::string foreign = server_->NewDatabase("foreign");
    server_->Sql(foreign, "CREATE TABLE invoices (id int)");
    ExpectRefused([&] { st::Push(Options(station, server_->Url(foreign))); },
                  "is not a gyrocal database", station);
    // a database without the schema
    ExpectRefused([&] { st::Push(Options(station, server_->Url(server_->NewDatabase("empty")))); },
                  "has no gyrocal schema", station);
    // a centre older than the station
    server_->Sql(db_name_, "UPDATE gyrocal_meta SET value = '8' WHERE key = 'schema_version'");
    ExpectRefused([&] { st::Push(o); }, "older than this station's", station);
    server_->Sql(db_name_, "UPDATE gyrocal_meta SET value = '" +
                               std::to_string(st::kSchemaVersion) +
                               "' WHERE key = 'schema_version'");
    // not a URL; a station file that is not a gyrocal database
    ExpectRefused([&] { st::Push(Options(station, "central.db")); },
                  "is not a central database URL", station);
    const std::string text = FreshDbPath("push_not_sqlite");
    std::ofstream(text) << "hello\n";
    ExpectRefused([&] { st::Push(Options(text, url_)); }, "is not an SQLite database", text);
}

TEST_F(CentralRefusals, AStationOfAnOlderSchemaPushesIntoANewerCentre) {
    // The centre was migrated by newer software: one more (additive) step than this station's.
    server_->Sql(db_name_,
                 "ALTER TABLE runs ADD COLUMN operator TEXT; UPDATE gyrocal_meta SET value = '" +
                     std::to_string(st::kSchemaVersion + 1) + "' WHERE key = 'schema_version'");
    const std::string station = FreshDbPath("push_older_station");
    WriteStation(station, {.prefix = "Y", .runs = 1});
    const st::PushReport r = PushAll(station);
    ASSERT_EQ(r.runs.size(), 1u);
    EXPECT_TRUE(r.runs[0].ok) << r.runs[0].error;
    // ... and this (older) software refuses to read the newer centre, as it does a newer file.
    try {
        st::OpenForQuery(url_);
        ADD_FAILURE() << "a newer centre was read";
    } catch (const st::StoreError& e) {
        EXPECT_NE(std::string(e.what()).find("newer than this software"), std::string::npos);
    }
}

TEST(CentralUrl, CredentialsAreNeverShown) {
    EXPECT_EQ(st::WithoutCredentials("postgresql://u:s3cret@host:5/db?sslmode=require"),
              "postgresql://u:***@host:5/db?sslmode=require");
    EXPECT_EQ(st::WithoutCredentials("postgres://u@h/db?password=s3cret&x=1"),
              "postgres://u@h/db?password=***&x=1");
    EXPECT_EQ(st::WithoutCredentials("gyrocal.db"), "gyrocal.db");
    EXPECT_EQ(st::WithoutCredentialsIn("gyrocal push --to postgresql://u:pw@h/db --db x"),
              "gyrocal push --to postgresql://u:***@h/db --db x");
    EXPECT_EQ(st::RedactCredentials("failed for pw and p%40w", "postgresql://u:p%40w@h/db"),
              "failed for pw and ***");
    EXPECT_TRUE(st::IsCentralUrl("postgresql://h/db"));
    EXPECT_FALSE(st::IsCentralUrl("/tmp/postgresql://x"));
}

TEST(CentralUrl, ParametersBecomeDollarParameters) {
    EXPECT_EQ(st::ToDollarParams("SELECT ?1, ?, '?', \"a?\" -- ?\n, ?3, ?"),
              "SELECT $1, $2, '?', \"a?\" -- ?\n, $3, $4");
}

}  // namespace
}  // namespace gyrocal::testing
