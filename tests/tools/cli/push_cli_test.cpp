// `gyrocal push`, `gyrocal central` and the store commands with --db postgresql://..., through the
// real `gyrocal` executable on a real PostgreSQL server (tests/store/pg_server.hpp):
//   - the centre gives the same answers as the station's file: runs, show, history, export (json,
//     csv, c-header, samples), analyze and validate (not stored), and the report page, compared
//     after the differences that must be there are taken out (ids: + run_key * 10^12 at the
//     centre; the database's name; the time the report was written; the station column);
//   - a push killed (SIGKILL) at random points and resumed ends with exactly the station's rows;
//   - the server restarted in the middle of a push: one line, exit 1, no half run; pushed again;
//   - bad input: one line, exit 1 (2 for bad options), the password never in what is printed.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "store/db/central_db.hpp"
#include "store/db/central_url.hpp"
#include "store/db/query.hpp"
#include "tests/processors/analysis/run_db.hpp"
#include "tests/store/pg_server.hpp"
#include "tests/store/scratch_db.hpp"
#include "tests/store/station_fixture.hpp"
#include "tests/store/table_digest.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
namespace st = gyrocal::db;
namespace fs = std::filesystem;

struct Cli {
    int code = -1;
    std::string out, err;
};

std::string Dir() {
    static const std::string d = [] {
        const std::string p = ::testing::TempDir() + "gyrocal_push_cli_" + std::to_string(getpid());
        fs::remove_all(p);
        fs::create_directories(p);
        return p;
    }();
    return d;
}

Cli Gyrocal(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {GYROCAL_CLI};
    argv.insert(argv.end(), args.begin(), args.end());
    launch::ChildProcess p(argv, Dir() + "/cli.out", Dir() + "/cli.err");
    const auto s = p.Wait(240s);
    return {s ? s->code : -1, launch::ReadLog(Dir() + "/cli.out"),
            launch::ReadLog(Dir() + "/cli.err")};
}

// A central id (run_key * 10^12 + station id: 13 digits, zeros after the first) as the station's.
std::string StationIds(const std::string& text) {
    static const std::regex id(R"(\b[1-9]0{6}0*([1-9][0-9]{0,5}|0)\b)");
    std::string out;
    std::sregex_iterator it(text.begin(), text.end(), id), end;
    size_t pos = 0;
    for (; it != end; ++it) {
        if (it->length(0) != 13) continue;
        out.append(text, pos, static_cast<size_t>(it->position(0)) - pos);
        out += (*it)[1].str();
        pos = static_cast<size_t>(it->position(0) + it->length(0));
    }
    return out + text.substr(pos);
}

// What must differ between the centre's answer and the station's taken out: ids, the database's
// name, "station" keys.
std::string Normalized(std::string text, const std::vector<std::string>& names) {
    for (const std::string& n : names) {
        for (size_t at = text.find(n); at != std::string::npos; at = text.find(n, at))
            text.replace(at, n.size(), "<DB>");
    }
    text = std::regex_replace(text, std::regex(R"(\n *"station": "[^"]*",?)"), "");
    return StationIds(text);
}

// A push cut short (killed, or its server restarted) leaves every run at the centre `url` whole
// or absent: each run there has the station's samples, all of them.
void ExpectRunsWholeOrAbsent(const std::string& url, st::Db& station) {
    auto c = st::OpenForQuery(url);
    for (const auto& r : st::ListRuns(*c, {})) {
        if (r.run_id.empty()) continue;
        EXPECT_EQ(r.gyro_samples, st::GetRun(station, r.run_id).gyro_samples) << r.run_id;
    }
}

// A push started again after that ends with exactly the station's rows of `runs` at the centre.
void ExpectPushAgainCompletes(const std::string& url, const std::string& station_path,
                              st::Db& station, const std::vector<std::string>& runs,
                              const std::string& trace) {
    const Cli again = Gyrocal({"push", "--to", url, "--db", station_path});
    ASSERT_EQ(again.code, 0) << again.err;
    auto c = st::OpenForQuery(url);
    for (const std::string& run : runs)
        EXPECT_EQ(RunDigests(*c, station, run), RunDigests(station, station, run)) << trace << run;
}

// The server and the roles are shared (CTest runs each test in a process of its own); each test
// makes its own central database and station files.
class PushCli : public ::testing::Test {
protected:
    void SetUp() override {
        server_ = &SharedPgServer();
        server_->EnsureRole("cli_pusher", "cli-pusher-pw9");
        server_->EnsureRole("cli_reader", "cli-reader-pw9");
        db_name_ = server_->NewDatabase("cli");
        admin_ = server_->Url(db_name_);
        push_url_ = server_->Url(db_name_, "cli_pusher", "cli-pusher-pw9");
        read_url_ = server_->Url(db_name_, "cli_reader", "cli-reader-pw9");
    }
    static void TearDownTestSuite() { fs::remove_all(Dir()); }

    // A station of two simulated runs of one unit (the analysis tests' runs, on a shorter
    // profile), each with the fitter's final set over its plateaus and rotations and its stop, R1
    // analysed (`gyrocal analyze`, stored).
    std::string SimStation() {
        const std::string path = Dir() + "/station.db";
        analysis::testing::SimRunOptions o;
        o.seed = 601;
        o.setpoints_c = {-10.0, 50.0, 20.0};
        analysis::testing::WriteSimRun(path, "R1", analysis::testing::MakeSimRun(o, true));
        o.noise_seed = 1601;
        o.start_utime = analysis::testing::MakeSimRun(o).config.start_utime + 86'400'000'000LL;
        analysis::testing::WriteSimRun(path, "R2", analysis::testing::MakeSimRun(o, true));
        {
            st::StoreWriter w(path, {"test", "station", 1});
            std::vector<st::Row> rows;
            for (const char* run : {"R1", "R2"}) {
                st::CoeffSetRow c;
                c.run_id = run;
                c.sensor_id = "S01";
                c.source = "fitter";
                c.coeff_set_id = 1;
                c.offset = StationModel("offset_v", {2.5, 1e-3, -2e-6});
                c.sensitivity = StationModel("sensitivity_v_per_dps", {0.0067, 1e-6});
                st::Stmt p(w.db(),
                           "SELECT plateau_id FROM plateaus WHERE run_id = ?1 UNION ALL "
                           "SELECT -rotation_id FROM sensitivity_points WHERE run_id = ?1");
                p.Bind(1, std::string(run));
                while (p.Step())
                    (p.Int(0) > 0 ? c.plateau_ids : c.rotation_ids).push_back(std::abs(p.Int(0)));
                c.recv_utime = std::string(run) == "R1" ? o.start_utime - 2000
                                                        : o.start_utime + 86'000'000'000LL;
                rows.push_back(c);
            }
            // after every row of its run: R1 ends before R2 starts, R2 a day after its start
            rows.push_back(RunEvent("R1", "stop", {"S01"}, o.start_utime - 1000));
            rows.push_back(RunEvent("R2", "stop", {"S01"}, o.start_utime + 86'400'000'000LL));
            w.Write(rows, {});
        }
        EXPECT_EQ(Gyrocal({"analyze", "R1", "--db", path}).code, 0);
        return path;
    }

    PgServer* server_ = nullptr;
    std::string db_name_, admin_, push_url_, read_url_;
};

TEST_F(PushCli, TheCentreAnswersAsTheStationsFileDoes) {
    const std::string station = SimStation();
    // GIVEN a central database made by its owner, a role that pushes and one that reads
    const Cli init = Gyrocal({"central", "init", "--db", admin_, "--grant-push", "cli_pusher",
                              "--grant-read", "cli_reader"});
    ASSERT_EQ(init.code, 0) << init.err;
    EXPECT_EQ(init.out.find(PgServer::kAdminPassword), std::string::npos) << init.out;
    // WHEN the station pushes what is new (as the pushing role)
    const Cli push = Gyrocal({"push", "--to", push_url_, "--db", station});
    ASSERT_EQ(push.code, 0) << push.err;
    EXPECT_NE(push.out.find("2 of 2 runs pushed"), std::string::npos) << push.out;
    EXPECT_EQ((push.out + push.err).find("cli-pusher-pw9"), std::string::npos);
    EXPECT_EQ(Gyrocal({"push", "--to", push_url_, "--db", station}).out,
              "nothing new to push to " + st::WithoutCredentials(push_url_) + "\n");
    // THEN every command gives the same answer from the centre (as the reading role)
    std::vector<std::string> names = {station, st::WithoutCredentials(read_url_)};
    names.push_back(std::regex_replace(names[1], std::regex("&"), "&amp;"));  // as HTML has it
    const std::vector<std::vector<std::string>> commands = {
        {"runs", "--json"},
        {"show", "R1", "--json"},
        {"show", "R2"},
        {"history", "S01", "--json"},
        {"history", "S01", "--all", "--json"},
        {"export", "R1", "--format", "json"},
        {"export", "R1", "--format", "csv"},
        {"export", "R1", "--format", "c-header"},
        {"export", "S01", "--format", "json"},
        {"export", "R2", "--format", "samples"},
        {"analyze", "R2", "--no-store", "--json"},
        {"validate", "R2", "--model-run", "R1", "--no-store", "--json"},
    };
    for (const auto& c : commands) {
        std::vector<std::string> here = c, there = c;
        here.insert(here.end(), {"--db", station});
        there.insert(there.end(), {"--db", read_url_});
        const Cli a = Gyrocal(here), b = Gyrocal(there);
        ASSERT_EQ(a.code, 0) << c[0] << ": " << a.err;
        ASSERT_EQ(b.code, 0) << c[0] << ": " << b.err;
        EXPECT_EQ(Normalized(b.out, names), Normalized(a.out, names)) << c[0] << " " << c[1];
        EXPECT_EQ((b.out + b.err).find("cli-reader-pw9"), std::string::npos);
    }
    // AND the report page is the same page (but the time it was written and the database named)
    const std::string out_a = Dir() + "/rep_station", out_b = Dir() + "/rep_centre";
    ASSERT_EQ(Gyrocal({"report", "R1", "--db", station, "--out", out_a}).code, 0);
    const Cli rb = Gyrocal({"report", "R1", "--db", read_url_, "--out", out_b});
    ASSERT_EQ(rb.code, 0) << rb.err;
    const std::regex written(R"(Written by gyrocal report (.*?) on [0-9-]+ [0-9:]+ UTC)");
    auto page = [&](const std::string& dir) {
        std::ifstream f(dir + "/report-R1.html");
        std::stringstream s;
        s << f.rdbuf();
        return Normalized(std::regex_replace(s.str(), written, "Written on <T>"), names);
    };
    const std::string pa = page(out_a), pb = page(out_b);
    EXPECT_GT(pa.size(), 10000u);
    EXPECT_EQ(pb, pa);
    // AND `analyze` at the centre without --no-store says where results are stored
    const Cli stored = Gyrocal({"analyze", "R2", "--db", read_url_});
    EXPECT_EQ(stored.code, 1);
    EXPECT_NE(stored.err.find("written only by gyrocal push"), std::string::npos) << stored.err;
}

TEST_F(PushCli, APushKilledAtRandomPointsAndResumedEndsWithExactlyTheStationsRows) {
    const std::string station = Dir() + "/big.db";
    WriteStation(station, {.prefix = "K", .runs = 3, .samples_per_sensor = 20000});
    auto s = st::OpenForQuery(station);
    // How long a whole push takes here (into a centre of its own), so that the kills below land
    // inside one whatever the machine's speed and load.
    const auto fresh_centre = [&] {
        const std::string url = server_->Url(server_->NewDatabase("killed"));
        EXPECT_EQ(Gyrocal({"central", "init", "--db", url}).code, 0);
        return url;
    };
    const std::string timed = fresh_centre();
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(Gyrocal({"push", "--to", timed, "--db", station}).code, 0);
    const auto whole = std::chrono::steady_clock::now() - t0;
    // Each round: a fresh centre, a push SIGKILLed at a random point of it (seeded: a failure
    // repeats), every run at the centre whole or absent, then the push resumed to the end.
    std::mt19937 rng(25);
    std::uniform_real_distribution<double> fraction(0.05, 0.9);
    int cut = 0;
    for (int round = 0; round < 5; ++round) {
        const std::string url = fresh_centre();
        launch::ChildProcess p({GYROCAL_CLI, "push", "--to", url, "--db", station},
                               Dir() + "/kill.out", Dir() + "/kill.err");
        // Time itself: the kill lands at a random point of the push's duration.
        std::this_thread::sleep_for(
            std::chrono::duration_cast<std::chrono::milliseconds>(whole * fraction(rng)));
        p.Signal(SIGKILL);
        const auto status = p.Wait(30s);
        ASSERT_TRUE(status.has_value());
        cut += status->exited ? 0 : 1;
        ExpectRunsWholeOrAbsent(url, *s);
        ExpectPushAgainCompletes(url, station, *s, {"K-R1", "K-R2", "K-R3"},
                                 std::to_string(round) + " ");
    }
    EXPECT_GE(cut, 3) << "most kills should land inside a push of " << whole.count() << " ns";
}

TEST_F(PushCli, AServerRestartedInTheMiddleOfAPushLosesNothing) {
    // A server of this test's own (the shared one serves other tests meanwhile).
    char tmpl[] = "/tmp/gyrocal-pg-restart-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    auto own = PgServer::Start(tmpl);
    const std::string url = own->Url("postgres");
    ASSERT_EQ(Gyrocal({"central", "init", "--db", url}).code, 0);
    const std::string station = Dir() + "/restart.db";
    WriteStation(station, {.prefix = "Z", .runs = 3, .samples_per_sensor = 100000});
    launch::ChildProcess p({GYROCAL_CLI, "push", "--to", url, "--db", station},
                           Dir() + "/restart.out", Dir() + "/restart.err");
    // The restart lands inside the push on any machine: the server is restarted as soon as the
    // push's first run is visible there (each run is one central transaction), with two runs of
    // 100k samples per sensor still to go, instead of after a fixed sleep that a fast machine
    // outruns.
    bool first_run_visible = false;
    while (!first_run_visible && !p.Wait(20ms)) {
        auto c = st::OpenForQuery(url);
        for (const auto& r : st::ListRuns(*c, {})) first_run_visible |= !r.run_id.empty();
    }
    ASSERT_FALSE(p.Wait(0ms).has_value())
        << "the push ended before the server could be restarted inside it: "
        << launch::ReadLog(Dir() + "/restart.out");
    own->Restart();
    const auto s = p.Wait(60s);
    ASSERT_TRUE(s.has_value());
    const std::string err = launch::ReadLog(Dir() + "/restart.err");
    EXPECT_EQ(s->code, 1) << "the push went on through the restart: "
                          << launch::ReadLog(Dir() + "/restart.out");
    EXPECT_NE(err.find("gyrocal push: error: central database"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    auto s_db = st::OpenForQuery(station);
    ExpectRunsWholeOrAbsent(url, *s_db);
    ExpectPushAgainCompletes(url, station, *s_db, {"Z-R1", "Z-R2", "Z-R3"}, "");
}

TEST_F(PushCli, BadInputIsOneLineAndExitOneAndThePasswordIsNeverPrinted) {
    const std::string station = Dir() + "/bad_input.db";
    WriteStation(station, {.prefix = "E", .runs = 1, .samples_per_sensor = 50});
    ASSERT_EQ(Gyrocal({"central", "init", "--db", admin_}).code, 0);
    const std::string secret = "s3cret-never-shown";
    const std::string wrong = server_->Url(db_name_, PgServer::kAdmin, secret);
    struct Case {
        std::vector<std::string> args;
        int code;
        std::string says;
    };
    const std::string nowhere = "postgresql://u:" + secret + "@/db?host=/nonexistent";
    const std::vector<Case> cases = {
        {{"push", "--to", wrong, "--db", station}, 1, "password authentication failed"},
        {{"push", "--to", nowhere, "--db", station}, 1, "cannot connect to central database"},
        {{"push", "--to", admin_, "--db", station, "NOPE"}, 1, "no run 'NOPE'"},
        {{"push", "--db", station}, 1, "no central database: give --to"},
        {{"push", "--to", admin_, "--db", Dir() + "/missing.db"}, 1, "does not exist"},
        {{"runs", "--db", wrong}, 1, "password authentication failed"},
        {{"show", "NOPE", "--db", admin_}, 1, "no run 'NOPE'"},
        {{"history", "U01", "--db", nowhere}, 1, "cannot connect"},
        {{"central", "status", "--db", wrong}, 1, "password authentication failed"},
        {{"push", "--to", admin_, "--bogus"}, 2, "--bogus"},
    };
    for (const Case& c : cases) {
        const Cli r = Gyrocal(c.args);
        EXPECT_EQ(r.code, c.code) << c.args[0] << " " << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
        if (c.code == 1) {
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        }
        EXPECT_EQ((r.out + r.err).find(secret), std::string::npos) << r.out << r.err;
    }
}

TEST_F(PushCli, APasswordFileServesAUrlWithoutPassword) {
    const std::string pgpass = Dir() + "/pgpass";
    {
        std::ofstream f(pgpass);
        f << "*:*:*:cli_reader:cli-reader-pw9\n";
    }
    fs::permissions(pgpass, fs::perms::owner_read | fs::perms::owner_write);
    ::setenv("PGPASSFILE", pgpass.c_str(), 1);
    const Cli r = Gyrocal({"central", "status", "--db", server_->Url(db_name_, "cli_reader", "")});
    ::unsetenv("PGPASSFILE");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("gyrocal schema version"), std::string::npos) << r.out;
}

TEST_F(PushCli, TheFleetAcrossStationsNamesTheOddUnitAndAStationApartAndDrawsThem) {
    // Four stations of one unit model: A and B alike, C's units 4 mV higher (a station bias),
    // D's one unit 50 mV off (an odd unit). Unit i sits i mV above its station's first.
    ASSERT_EQ(Gyrocal({"central", "init", "--db", admin_}).code, 0);
    struct S {
        const char* prefix;
        int units;
        double offset_v;
    };
    for (const S& s : {S{"A", 4, 0}, S{"B", 4, 0}, S{"C", 4, 0.004}, S{"D", 1, 0.05}}) {
        StationSpec spec{.prefix = s.prefix,
                         .runs = 1,
                         .samples_per_sensor = 20,
                         .station_offset_v = s.offset_v,
                         .unit_offset_v = 0.001};
        spec.sensors.clear();
        for (int i = 1; i <= s.units; ++i) spec.sensors.push_back(s.prefix + std::to_string(i));
        const std::string path = Dir() + "/fleet_" + s.prefix + ".db";
        WriteStation(path, spec);
        ASSERT_EQ(Gyrocal({"push", "--to", admin_, "--db", path}).code, 0);
    }
    const std::string plots = Dir() + "/fleet_plots";
    const Cli text = Gyrocal({"fleet", "--db", admin_, "--plot", plots});
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("model myGyro610EB: 13 units from 4 stations"), std::string::npos)
        << text.out;
    const Cli j = Gyrocal({"fleet", "--db", admin_, "--json"});
    ASSERT_EQ(j.code, 0) << j.err;
    const json g = json::parse(j.out).at(0);
    // The odd unit is outside; none of A's, B's or C's (C's shift is within the lot's spread).
    std::set<std::string> outside;
    for (const auto& d : g["outside"]) outside.insert(d["sensor_id"].get<std::string>());
    EXPECT_EQ(outside, std::set<std::string>{"D1"}) << j.out;
    // C sits above the lot: the highest station median z of A, B and C.
    ASSERT_EQ(g["stations"].size(), 4u);
    for (const auto& png : {"fleet_myGyro610EB_offset.png", "fleet_myGyro610EB_sensitivity.png"})
        EXPECT_TRUE(fs::exists(fs::path(plots) / png)) << png;
    double c_z = 0, ab_z = -1e9;
    for (const auto& st : g["stations"]) {
        const std::string name = st["station"];
        const double v = st["offset_median_z"];
        if (name.find("fleet_C") != std::string::npos) c_z = v;
        if (name.find("fleet_A") != std::string::npos || name.find("fleet_B") != std::string::npos)
            ab_z = std::max(ab_z, v);
    }
    EXPECT_GT(c_z, ab_z + 1.0) << j.out;
}

TEST_F(PushCli, ConnectionsAreEncryptedWhenTheServerOffersTls) {
    // A server of its own on 127.0.0.1 with TLS on (self-signed); libpq's default sslmode=prefer.
    char tmpl[] = "/tmp/gyrocal-pg-tls-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    auto tls = PgServer::StartWithTls(tmpl);
    const std::string url = "postgresql://" + std::string(PgServer::kAdmin) + ":" +
                            PgServer::kAdminPassword +
                            "@127.0.0.1:" + std::to_string(tls->tcp_port()) + "/postgres";
    ASSERT_EQ(Gyrocal({"central", "init", "--db", url}).code, 0);
    const Cli on = Gyrocal({"central", "status", "--db", url});
    EXPECT_NE(on.out.find("connection encrypted (TLS)"), std::string::npos) << on.out << on.err;
    const Cli off = Gyrocal({"central", "status", "--db", url + "?sslmode=disable"});
    EXPECT_NE(off.out.find("not encrypted"), std::string::npos) << off.out << off.err;
    const std::string station = Dir() + "/tls.db";
    WriteStation(station, {.prefix = "T", .runs = 1, .samples_per_sensor = 100});
    const Cli push = Gyrocal({"push", "--to", url + "?sslmode=require", "--db", station});
    EXPECT_EQ(push.code, 0) << push.err;
    EXPECT_EQ((on.out + push.out + push.err).find(PgServer::kAdminPassword), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::testing
