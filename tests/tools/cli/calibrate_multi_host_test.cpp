// Several hosts for real: three network namespaces on a bridge (tests/support/netns), the
// producers on h1, the processors on h2, the recorder and the CLI on h3, each started the way a
// lab starts them: `gyrocal calibrate --role R` with the same options and an LCM URL with ttl=1.
// Ports of this file: 7805 (the single-host run), 7806 and 7807 (the labs).
//
// 1. The rig's own procedure (--procedure rig, data time only) on three hosts gives the same
//    database as on one host, sample for sample.
// 2. A pulled cable on the producers' host during an averaging window and during a turn: every
//    message that arrived is stored, every gap is counted per channel, the window and the turn
//    are refused (not fitted over the hole) and taken again, and the run completes.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <iostream>
#include <mutex>

#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/support/netns/netns_lab.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using testing::NetnsLab;

// A lab's bus: TTL 1 crosses the namespaces' bridge.
std::string LabUrl(int port) { return UdpmUrl(port, 1); }

// Short simulated profile: fast thermal constants, three setpoints 15 degC apart, two units.
std::vector<std::string> Common(const std::string& procedure, const std::string& seed,
                                const std::string& speed) {
    std::vector<std::string> a = {"--procedure",
                                  procedure,
                                  "--setpoints-c",
                                  "15,30,45",
                                  "--sensors",
                                  "2",
                                  "--seed",
                                  seed,
                                  "--speed",
                                  speed,
                                  "--await-peers-s",
                                  "60",
                                  "--rig-arg=--package-tau-s=20",
                                  "--rig-arg=--ramp-c-per-min=20",
                                  "--rig-arg=--air-tau-s=10",
                                  "--wall-timeout-s",
                                  "400"};
    if (procedure == "rig") a.push_back("--rig-arg=--dwell-s=330");
    if (procedure == "sequencer") a.push_back("--sequencer-arg=--ramp-rate-c-per-min=20");
    return a;
}

struct Roles {
    std::unique_ptr<launch::ChildProcess> recorder, processors, producers;
    std::string dir;
};

// Starts the three roles on h3, h2, h1 (consumers first: docs/lab.md#a-lab-on-several-hosts).
Roles StartLab(const NetnsLab& lab, const std::string& dir, const std::string& url,
               const std::vector<std::string>& common) {
    Roles r;
    r.dir = dir;
    auto start = [&](int host, const std::string& role) {
        std::vector<std::string> argv = {
            GYROCAL_CLI, "calibrate", "--role",        role,        "--lcm-url",
            url,         "--db",      dir + "/lab.db", "--log-dir", dir + "/" + role};
        argv.insert(argv.end(), common.begin(), common.end());
        return lab.Start(host, argv, dir + "/" + role + ".out");
    };
    r.recorder = start(3, "recorder");
    r.processors = start(2, "processors");
    r.producers = start(1, "producers");
    return r;
}

void ExpectAllEndedWell(Roles& r) {
    for (auto* p : {&r.producers, &r.processors, &r.recorder}) {
        const auto st = (*p)->Wait(450s);
        const std::string log = r.dir + "/" +
                                (p == &r.producers    ? "producers"
                                 : p == &r.processors ? "processors"
                                                      : "recorder") +
                                ".out";
        ASSERT_TRUE(st.has_value()) << "did not end:\n" << launch::ReadLog(log);
        EXPECT_TRUE(st->exited && st->code == 0) << st->Describe() << "\n" << launch::ReadLog(log);
    }
}

std::string OnlyRun(Sql& sql) {
    return sql.Rows("SELECT run_id FROM runs WHERE run_id <> ''").at(0).at(0);
}

// Rows of `select` in one database and not the other, both ways.
int64_t Differing(Sql& sql, const std::string& select_main, const std::string& select_other) {
    return sql.Int("SELECT count(*) FROM (" + select_main + " EXCEPT " + select_other + ")") +
           sql.Int("SELECT count(*) FROM (" + select_other + " EXCEPT " + select_main + ")");
}

TEST(MultiHost, ThreeHostsRecordTheSameRunAsOneHostSampleForSample) {
    if (const std::string why = NetnsLab::Unavailable(); !why.empty()) GTEST_SKIP() << why;
    const std::string dir = FreshDir("gyrocal_multihost");
    // --speed 20: 6000 messages/s, each crossing the bridge to two other hosts; at 40 a loaded
    // CI host lost samples in the lab run, and a lost sample is a different database.
    const auto common = Common("rig", "11", "20");
    // GIVEN the run on one host (TTL 0, this machine's loopback)
    {
        std::vector<std::string> argv = {GYROCAL_CLI,        "calibrate",  "--db",
                                         dir + "/single.db", "--log-dir",  dir + "/single",
                                         "--lcm-url",        UdpmUrl(7805)};
        argv.insert(argv.end(), common.begin(), common.end());
        launch::ChildProcess single(argv, dir + "/single.out", dir + "/single.out");
        const auto st = single.Wait(450s);
        ASSERT_TRUE(st && st->exited && st->code == 0) << launch::ReadLog(dir + "/single.out");
    }
    // WHEN the same options run as three hosts' roles
    NetnsLab lab("gcmh", 3, 202);
    Roles roles = StartLab(lab, dir, LabUrl(7806), common);
    ExpectAllEndedWell(roles);
    if (HasFatalFailure()) return;

    // THEN the recorder's database holds exactly the single-host run: every sample, plateau,
    // sensitivity point and the final coefficients, to the last bit (the procedure runs on data
    // time; only run ids and reception times differ).
    Sql sql(dir + "/lab.db");
    sql.Attach(dir + "/single.db", "one");
    const std::string run = OnlyRun(sql);
    EXPECT_EQ(sql.Rows("SELECT outcome, reason FROM runs WHERE run_id = '" + run + "'").at(0).at(0),
              "stop");
    const int64_t samples = sql.Int("SELECT count(*) FROM main.gyro_samples");
    EXPECT_EQ(samples, sql.Int("SELECT count(*) FROM one.gyro_samples"));
    EXPECT_GT(samples, 200000) << "two units at 100 Hz for ~23 simulated minutes";
    // What arrived is the single-host run's; anything missing would be counted (then the rest of
    // the comparison below cannot hold, and says where).
    EXPECT_EQ(sql.Int("SELECT count(*) FROM (SELECT sensor_id, seq, gyro_v FROM main.gyro_samples "
                      "EXCEPT SELECT "
                      "sensor_id, seq, gyro_v FROM one.gyro_samples)"),
              0);
    EXPECT_EQ(
        sql.Int("SELECT count(*) FROM one.gyro_samples") - samples,
        sql.Int("SELECT coalesce(sum(seq_gaps), 0) FROM main.losses WHERE channel LIKE 'GYRO_%'"));
    EXPECT_EQ(sql.Int("SELECT count(*) FROM main.plateaus"), 6);
    EXPECT_EQ(sql.Int("SELECT count(*) FROM main.sensitivity_points WHERE accepted = 1"), 12);
    // Every column the procedure's data time decides, table by table.
    const std::vector<std::pair<std::string, std::string>> compared = {
        {"gyro_samples",
         "sensor_id, seq, utime, gyro_v, temp_v, temp_c, supply_v, gyro_counts, temp_counts"},
        {"encoder_samples", "encoder_id, seq, utime, counts, angle_deg"},
        {"chamber_states", "seq, utime, setpoint_c, air_c, at_setpoint"},
        {"plateaus",
         "sensor_id, plateau_id, start_utime, end_utime, first_seq, last_seq, n_samples, seq_gaps, "
         "temp_mean_c, gyro_mean_v, gyro_sem_v, temp_sem_c"},
        {"sensitivity_points",
         "sensor_id, rotation_id, n_samples, accepted, encoder_angle_deg, sensitivity_v_per_dps, "
         "sensitivity_stderr_v_per_dps"}};
    for (const auto& [table, columns] : compared) {
        EXPECT_EQ(Differing(sql, "SELECT " + columns + " FROM main." + table,
                            "SELECT " + columns + " FROM one." + table),
                  0)
            << table;
    }
    // The final set's id is the stop event's time, which the launcher stamps from its own clock
    // like the run id: compared are the sets' terms, not their ids.
    auto final_terms = [](const std::string& db) {
        return "SELECT c.sensor_id, t.role, t.term_name, t.coeff FROM " + db +
               ".coeff_sets c JOIN " + db +
               ".coeff_terms t ON t.coeff_row_id = c.coeff_row_id WHERE c.coeff_row_id = (SELECT "
               "d.coeff_row_id FROM " +
               db +
               ".coeff_sets d WHERE d.sensor_id = c.sensor_id ORDER BY d.recv_utime DESC, "
               "d.coeff_row_id DESC LIMIT 1)";
    };
    EXPECT_GE(sql.Int("SELECT count(*) FROM (" + final_terms("main") + ")"), 8)
        << "two sensors, offset + sensitivity";
    EXPECT_EQ(Differing(sql, final_terms("main"), final_terms("one")), 0);
    EXPECT_EQ(
        sql.Int("SELECT coalesce(sum(seq_gaps + decode_errors + queue_drops), 0) FROM main.losses"),
        0);
    // Every process of the graph was heard (the rig's own procedure has no sequencer).
    EXPECT_EQ(
        sql.Int("SELECT count(DISTINCT process) FROM main.status WHERE process LIKE 'gyrocal-%'"),
        6);

    // The CLI on the recorder's host reads it.
    auto show =
        lab.Start(3, {GYROCAL_CLI, "show", run, "--db", dir + "/lab.db"}, dir + "/show.out");
    const auto st = show->Wait(60s);
    ASSERT_TRUE(st && st->exited && st->code == 0) << launch::ReadLog(dir + "/show.out");
    EXPECT_NE(launch::ReadLog(dir + "/show.out").find("none recorded"), std::string::npos)
        << "no losses";
}

// Watches the bus from the recorder's host and pulls the producers' cable twice: during an
// averaging window of the second setpoint and right at the first turn of the third.
struct CablePuller {
    CablePuller(const NetnsLab& l, double plateau_s, double turn_s)
        : lab(l), plateau_cut_s(plateau_s), turn_cut_s(turn_s) {}
    const NetnsLab& lab;
    double plateau_cut_s, turn_cut_s;
    std::atomic<bool> stop{false};
    std::atomic<int> cuts{0};
    std::mutex mu;
    std::string log;

    void Run(const std::string& url) {
        bus::Bus bus(bus::BusOptions{url});
        int stage = 0;  // 0: wait setpoint 2 averaging; 1: wait turn at setpoint 3; 2: done
        int setpoint = -1;
        bool cut_now = false;
        bus.Subscribe<run_event_t>(
            std::string(channels::kRunEvent), [&](const run_event_t& e, const std::string&) {
                if (e.event == "setpoint") setpoint = e.setpoint_index;
                if (stage == 1 && e.event == "rotation" && e.setpoint_index == 2) cut_now = true;
            });
        bus.Subscribe<plateau_state_t>(channels::AllSensors(channels::kStabilityPrefix),
                                       [&](const plateau_state_t& s, const std::string&) {
                                           if (stage == 0 && setpoint == 1 &&
                                               s.state == "averaging" &&
                                               s.averaging_progress >= 0.3)
                                               cut_now = true;
                                       });
        while (!stop && stage < 2) {
            bus.Handle(5ms);
            if (!cut_now) continue;
            cut_now = false;
            const double hold_s = stage == 0 ? plateau_cut_s : turn_cut_s;
            lab.SetLink(1, false);
            // The fault's stated length, not a synchronisation: the cable stays out this long.
            std::this_thread::sleep_for(std::chrono::duration<double>(hold_s));
            lab.SetLink(1, true);
            ++cuts;
            std::lock_guard<std::mutex> l(mu);
            log += std::string(stage == 0 ? "plateau" : "turn") + " cut " + std::to_string(hold_s) +
                   " s\n";
            ++stage;
        }
        while (!stop) bus.Handle(50ms);  // drain until the run is over
    }
};

TEST(MultiHost, CableOutDuringAPlateauAndATurnIsCountedRefusedAndTakenAgain) {
    if (const std::string why = NetnsLab::Unavailable(); !why.empty()) GTEST_SKIP() << why;
    const std::string dir = FreshDir("gyrocal_linkcut");
    const std::string speed = "20";
    NetnsLab lab("gclc", 3, 203);
    CablePuller puller(lab, 2.0, 1.0);
    std::thread watch = lab.OnHost(3, [&] { puller.Run(LabUrl(7807)); });
    Roles roles = StartLab(lab, dir, LabUrl(7807), Common("sequencer", "5", speed));
    ExpectAllEndedWell(roles);
    puller.stop = true;
    watch.join();
    if (HasFatalFailure()) return;
    ASSERT_EQ(puller.cuts.load(), 2) << "the run ended before both faults were applied:\n"
                                     << puller.log;

    Sql sql(dir + "/lab.db");
    const std::string run = OnlyRun(sql);
    const auto outcome =
        sql.Rows("SELECT outcome, reason FROM runs WHERE run_id = '" + run + "'").at(0);
    EXPECT_EQ(outcome.at(0), "stop");
    EXPECT_EQ(outcome.at(1).rfind("completed", 0), 0u) << outcome.at(1);

    // Every gyro sample that reached the recorder is stored, and every one that did not is
    // counted as a gap of its channel: stored + gaps = the stream's whole seq range.
    int64_t lost_total = 0;
    for (const auto& r : sql.Rows(GyroStreamsSql(run))) {
        SCOPED_TRACE(r[0]);
        ASSERT_FALSE(r[3].empty()) << "no losses row for the channel";
        EXPECT_EQ(std::stoll(r[1]) + std::stoll(r[3]), std::stoll(r[2]));
        // 3 s of cable out at 100 Hz and --speed 20 is 6000 samples; a cut starts and ends
        // between samples, and the bridge port takes a moment to forward again: at least 90 %.
        EXPECT_GE(std::stoll(r[3]), 5400);
        lost_total += std::stoll(r[3]);
        std::cout << "[ figures ] " << r[0] << ": stored " << r[1] << ", lost " << r[3]
                  << " samples\n";
    }
    EXPECT_EQ(sql.Int("SELECT coalesce(sum(queue_drops + decode_errors), 0) FROM losses"), 0);
    EXPECT_GT(
        sql.Int("SELECT seq_gaps FROM losses WHERE channel = 'ENCODER' AND run_id = '" + run + "'"),
        0);

    // The window with the hole was refused and taken again: no stored plateau has a gap, each
    // sensor has one per setpoint, and the detector said why in its STATUS.
    EXPECT_EQ(sql.Int("SELECT count(*) FROM plateaus WHERE seq_gaps <> 0"), 0);
    EXPECT_EQ(
        sql.Int("SELECT count(*) FROM (SELECT sensor_id FROM plateaus GROUP BY sensor_id HAVING "
                "count(DISTINCT setpoint_c) = 3)"),
        2);
    EXPECT_GT(
        sql.Int("SELECT count(*) FROM status WHERE process = 'gyrocal-plateau' AND "
                "last_reject LIKE '%averaging window refused%samples missing (sequence gap%'"),
        0);
    // The turn that lost samples was not fitted: rejected for its hole or never completed, and
    // ordered again; the accepted points hold no gap (first_seq..last_seq all received).
    EXPECT_GT(sql.Int("SELECT count(*) FROM run_events WHERE event = 'rotation' AND reason LIKE "
                      "'%attempt 2 of 2%'"),
              0);
    // Rejections are for the hole: samples missing inside the turn's windows, or a rest window
    // left without samples by it.
    EXPECT_EQ(sql.Int("SELECT count(*) FROM sensitivity_points WHERE accepted = 0 AND "
                      "reject_reason NOT LIKE '%missing%' "
                      "AND reject_reason NOT LIKE 'rest window % covers %'"),
              0);
    for (const auto& p : sql.Rows(
             "SELECT sensor_id, first_seq, last_seq FROM sensitivity_points WHERE accepted = 1"))
        EXPECT_EQ(sql.Int("SELECT count(*) FROM gyro_samples WHERE sensor_id = '" + p[0] +
                          "' AND seq BETWEEN " + p[1] + " AND " + p[2]),
                  std::stoll(p[2]) - std::stoll(p[1]) + 1);
    // Calibrated from the rest: a final set per sensor from its three plateaus.
    EXPECT_EQ(sql.Int("SELECT count(DISTINCT sensor_id) FROM coeff_sets c JOIN coeff_models m ON "
                      "m.coeff_row_id = "
                      "c.coeff_row_id WHERE m.role = 'offset' AND m.n_points = 3"),
              2);

    // Shown by `gyrocal show` and by the progress line of the recorder's host.
    auto show =
        lab.Start(3, {GYROCAL_CLI, "show", run, "--db", dir + "/lab.db"}, dir + "/show.out");
    ASSERT_TRUE(show->Wait(60s));
    const std::string shown = launch::ReadLog(dir + "/show.out");
    EXPECT_NE(shown.find("GYRO_S01"), std::string::npos) << shown;
    const std::string printed = launch::ReadLog(dir + "/recorder.out");
    const std::string said =
        "losses seen on the bus (sequence gaps + decode errors + queue drops + handler errors): ";
    const size_t at = printed.find(said);
    ASSERT_NE(at, std::string::npos) << printed;
    EXPECT_GT(std::stoll(printed.substr(at + said.size())), 0) << printed.substr(at);
    std::cout << "[ figures ] " << puller.log << "[ figures ] lost in all: " << lost_total
              << " gyro samples\n";
}

}  // namespace
}  // namespace gyrocal
