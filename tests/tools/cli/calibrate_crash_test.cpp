// SIGKILL each kind of process of a running calibration and check what `gyrocal calibrate`, the
// supervisor, promises for it (lab.hpp, docs/faults.md): plateau, rotation, fitter, compensator,
// recorder and sequencer are restarted with their state recovered and the run completes; the
// rig takes its simulated chamber with it, so the run is aborted with that reason. Nothing
// committed is lost, the file stays intact, and what was missed shows as gaps.
// Single host, TTL 0, this file's ports 7808 and 7809. The six recoverable kills share one run:
// each is triggered by its own moment of the procedure and recovered before the next.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// The pid of `parent`'s child running `name` (as the kernel shortens it to 15 characters).
pid_t ChildPid(pid_t parent, const std::string& name) {
    for (const auto& e : std::filesystem::directory_iterator("/proc")) {
        const std::string n = e.path().filename();
        if (n.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream f(e.path() / "stat");
        std::string stat;
        std::getline(f, stat);
        const size_t open = stat.find('('), close = stat.rfind(')');
        if (open == std::string::npos || close == std::string::npos) continue;
        const std::string comm = stat.substr(open + 1, close - open - 1);
        std::istringstream rest(stat.substr(close + 2));
        char state;
        pid_t ppid = 0;
        rest >> state >> ppid;
        if (ppid == parent && comm == name.substr(0, 15)) return static_cast<pid_t>(std::stoi(n));
    }
    return -1;
}

std::vector<std::string> CalibrateArgs(const std::string& dir, int port,
                                       const std::string& setpoints) {
    return {GYROCAL_CLI,
            "calibrate",
            "--setpoints-c",
            setpoints,
            "--sensors",
            "2",
            "--seed",
            "3",
            "--speed",
            "40",
            "--db",
            dir + "/run.db",
            "--log-dir",
            dir + "/logs",
            "--quiet",
            "--wall-timeout-s",
            "400",
            "--lcm-url",
            UdpmUrl(port),
            "--rig-arg=--package-tau-s=20",
            "--rig-arg=--ramp-c-per-min=20",
            "--rig-arg=--air-tau-s=10",
            "--sequencer-arg=--ramp-rate-c-per-min=20"};
}

// A moment of the procedure, seen on the bus, at which one process is killed.
struct Kill {
    std::string process;
    std::function<bool(const run_event_t*, const plateau_state_t*)> when;
    std::string moment;
    bool done;
};

bool EventAt(const run_event_t* e, const char* event, int setpoint,
             const char* reason_prefix = "") {
    return e && e->event == event && e->setpoint_index == setpoint &&
           e->reason.rfind(reason_prefix, 0) == 0;
}

// Watches the run on `url` and kills each process at its moment; returns how calibrate ended.
std::optional<launch::ExitStatus> RunAndKill(launch::ChildProcess& cal, const std::string& url,
                                             std::vector<Kill>& kills,
                                             const std::function<void(const Kill&)>& before_kill) {
    bus::Bus bus(bus::BusOptions{url});
    int setpoint = -1;
    auto check = [&](const run_event_t* e, const plateau_state_t* s) {
        for (Kill& k : kills) {
            if (k.done || !k.when(e, s)) continue;
            const pid_t pid = ChildPid(cal.pid(), k.process);
            if (pid <= 0) continue;  // between a death and its restart: try at the next moment
            before_kill(k);
            ::kill(pid, SIGKILL);
            k.done = true;
            std::cout << "[ kill ] " << k.process << " (pid " << pid << ") at " << k.moment << "\n";
            break;  // one kill per moment
        }
    };
    bus.Subscribe<run_event_t>(std::string(channels::kRunEvent),
                               [&](const run_event_t& e, const std::string&) {
                                   if (e.event == "setpoint") setpoint = e.setpoint_index;
                                   check(&e, nullptr);
                               });
    bus.Subscribe<plateau_state_t>(channels::AllSensors(channels::kStabilityPrefix),
                                   [&](const plateau_state_t& s, const std::string&) {
                                       plateau_state_t at = s;
                                       at.last_plateau_id =
                                           setpoint;  // carries the setpoint index to `when`
                                       check(nullptr, &at);
                                   });
    const auto deadline = Clock::now() + 450s;
    while (Clock::now() < deadline) {
        bus.Handle(5ms);
        if (auto st = cal.Poll()) return st;
    }
    return std::nullopt;
}

bool Averaging(const plateau_state_t* s, int setpoint) {
    return s && s->last_plateau_id == setpoint && s->state == "averaging" &&
           s->averaging_progress >= 0.3;
}

TEST(CalibrateCrash, EveryRecoverableProcessKilledMidRunIsRestartedAndTheRunCompletes) {
    const std::string dir = FreshDir("gyrocal_crash");
    const int port = 7808;
    std::vector<Kill> kills = {
        {"gyrocal-plateau", [](auto*, auto* s) { return Averaging(s, 0); }, "setpoint 1, averaging",
         false},
        {"gyrocal-rotation", [](auto* e, auto*) { return EventAt(e, "rotation", 0, "move -90"); },
         "setpoint 1, -90 turn ordered", false},
        {"gyrocal-fitter", [](auto* e, auto*) { return EventAt(e, "setpoint", 1); },
         "setpoint 2 ordered", false},
        {"gyrocal-recorder", [](auto*, auto* s) { return Averaging(s, 1); },
         "setpoint 2, averaging", false},
        {"gyrocal-sequencer", [](auto* e, auto*) { return EventAt(e, "rotation", 1, "move 90"); },
         "setpoint 2, +90 turn ordered", false},
        // Late: a compensator only has coefficients to get back once the third plateau is in.
        {"gyrocal-compensator", [](auto* e, auto*) { return EventAt(e, "setpoint", 3); },
         "setpoint 4 ordered", false},
    };
    launch::ChildProcess cal(CalibrateArgs(dir, port, "15,30,45,30"), dir + "/out.txt",
                             dir + "/out.txt");
    int64_t committed_rowid = -1, committed_rows = -1;
    const auto st = RunAndKill(
        cal, "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0", kills, [&](const Kill& k) {
            if (k.process != "gyrocal-recorder") return;
            Sql before(dir + "/run.db");  // what another reader saw committed just before the kill
            committed_rowid = before.Int("SELECT coalesce(max(rowid), 0) FROM gyro_samples");
            committed_rows = before.Int("SELECT count(*) FROM gyro_samples");
        });
    const std::string printed = launch::ReadLog(dir + "/out.txt");
    ASSERT_TRUE(st.has_value()) << "calibrate did not end:\n" << printed;
    for (const Kill& k : kills)
        EXPECT_TRUE(k.done) << k.process << " was never killed (" << k.moment << ")";
    EXPECT_TRUE(st->exited && st->code == 0) << st->Describe() << "\n" << printed;

    Sql sql(dir + "/run.db");
    EXPECT_EQ(sql.Rows("PRAGMA integrity_check").at(0).at(0), "ok");
    const std::string run = sql.Rows("SELECT run_id FROM runs WHERE run_id <> ''").at(0).at(0);
    EXPECT_EQ(sql.Rows("SELECT outcome FROM runs WHERE run_id = '" + run + "'").at(0).at(0),
              "stop");
    // Each kill is in the run's history as a restart naming the process and its recovery.
    std::set<std::string> restarted;
    for (const auto& r :
         sql.Rows("SELECT config_json FROM run_events WHERE event = 'restart' AND run_id = '" +
                  run + "'"))
        restarted.insert(nlohmann::json::parse(r[0]).at("process").get<std::string>());
    EXPECT_EQ(restarted, (std::set<std::string>{"gyrocal-plateau", "gyrocal-rotation",
                                                "gyrocal-fitter", "gyrocal-recorder",
                                                "gyrocal-sequencer", "gyrocal-compensator"}));
    // Recorder: what was committed before the kill is all there; the restarted recorder continued
    // the same run, and what it missed while down is counted, exactly, as gaps.
    EXPECT_EQ(sql.Int("SELECT count(*) FROM gyro_samples WHERE rowid <= " +
                      std::to_string(committed_rowid)),
              committed_rows);
    EXPECT_EQ(
        sql.Int("SELECT count(*) FROM recorder_sessions WHERE resumed_run_id = '" + run + "'"), 1);
    int64_t gaps = 0;
    for (const auto& r : sql.Rows(GyroStreamsSql(run))) {
        ASSERT_FALSE(r[3].empty()) << r[0] << ": the recorder's downtime left no gap?";
        EXPECT_EQ(std::stoll(r[1]) + std::stoll(r[3]), std::stoll(r[2])) << r[0];
        EXPECT_GT(std::stoll(r[3]), 0) << r[0];
        gaps += std::stoll(r[3]);
    }
    // The restarted recorder continued the run: nothing it stored after its restart until the
    // stop went to another run (the no-run bucket '' holds only the discovery before the start,
    // samples overtaking the start event, and the rig's last samples after the stop).
    EXPECT_EQ(sql.Int("SELECT count(*) FROM gyro_samples WHERE run_id <> '" + run +
                      "' AND recv_utime > (SELECT "
                      "recv_utime FROM run_events WHERE event = 'restart' AND config_json LIKE "
                      "'%gyrocal-recorder%') "
                      "AND utime < (SELECT utime FROM run_events WHERE event = 'stop')"),
              0);
    // Fitter: its state came back from the database: the final set of each sensor uses plateaus
    // of all three setpoints, the first of them taken before the fitter died (the resumed
    // sequencer took setpoint 2 again, so there are two of it). Rotation: the turn it died in
    // was ordered again: every setpoint has both turns accepted in the final set.
    const std::string fitter_killed =
        sql.Rows(
               "SELECT recv_utime FROM run_events WHERE event = 'restart' AND "
               "config_json LIKE '%gyrocal-fitter%'")
            .at(0)
            .at(0);
    for (const std::string id : {"S01", "S02"}) {
        // The plateau set (the closed loop's final set is fitted on the bins it received).
        const std::string row =
            sql.Rows("SELECT coeff_row_id FROM coeff_sets WHERE sensor_id = '" + id +
                     "' AND source = 'fitter' ORDER BY recv_utime DESC LIMIT 1")
                .at(0)
                .at(0);
        const std::string used =
            " FROM coeff_set_plateaus l JOIN plateaus p ON p.plateau_id = l.plateau_id AND "
            "p.sensor_id = '" +
            id + "' WHERE l.coeff_row_id = " + row;
        EXPECT_EQ(sql.Int("SELECT count(DISTINCT p.setpoint_c)" + used), 3) << id;
        EXPECT_GT(sql.Int("SELECT count(*)" + used + " AND p.recv_utime < " + fitter_killed), 0)
            << id;
        EXPECT_EQ(
            sql.Int(
                // Setpoints 15, 30, 45 degC: temp_c / 15 rounds to the setpoint's index whatever
                // the few tenths the die sits from it (rounding to tens split 15 and 45 degC).
                "SELECT count(DISTINCT round(s.temp_c / 15.0) || '/' || s.direction) FROM "
                "coeff_set_rotations l "
                "JOIN sensitivity_points s ON s.rotation_id = l.rotation_id AND s.sensor_id = '" +
                id + "' WHERE l.coeff_row_id = " + row),
            6)
            << id;
    }
    EXPECT_EQ(
        sql.Int("SELECT count(*) - count(DISTINCT sensor_id || '/' || plateau_id) FROM plateaus"),
        0)
        << "the fitter's recovery published stored plateaus again: kept once";
    EXPECT_GT(
        sql.Int(
            "SELECT count(*) FROM run_events WHERE event = 'rotation' AND setpoint_index = 0 AND "
            "reason LIKE 'move -90 deg (attempt 2 of 2%'"),
        0);
    // Sequencer: resumed its run (no second start) at the setpoint it was at.
    EXPECT_EQ(sql.Int("SELECT count(*) FROM run_events WHERE event = 'start'"), 1);
    EXPECT_EQ(
        sql.Int("SELECT count(*) FROM run_events WHERE event = 'setpoint' AND setpoint_index = 1"),
        2);
    // Compensator: got the newest coefficients back from the database; its last rates use them.
    EXPECT_NE(printed.find("recovered gyrocal-compensator: published 2 coefficient sets"),
              std::string::npos)
        << printed;
    EXPECT_EQ(
        sql.Int(
            "SELECT count(*) FROM (SELECT coeff_set_id FROM rates ORDER BY rowid DESC LIMIT 200) "
            "WHERE coeff_set_id < 0"),
        0);
    std::cout << "[ figures ] gyro samples missed while the recorder was down: " << gaps << "\n";
}

TEST(CalibrateCrash, KilledRigAbortsTheRunWithTheReasonAndKeepsWhatWasRecorded) {
    const std::string dir = FreshDir("gyrocal_crash_rig");
    const int port = 7809;
    std::vector<Kill> kills = {{"gyrocal-sim-rig", [](auto*, auto* s) { return Averaging(s, 0); },
                                "setpoint 1, averaging", false}};
    launch::ChildProcess cal(CalibrateArgs(dir, port, "15,30,45"), dir + "/out.txt",
                             dir + "/out.txt");
    const auto st = RunAndKill(cal, "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0",
                               kills, [](const Kill&) {});
    const std::string printed = launch::ReadLog(dir + "/out.txt");
    ASSERT_TRUE(st.has_value()) << printed;
    ASSERT_TRUE(kills[0].done);
    EXPECT_TRUE(st->exited && st->code == 3) << st->Describe() << "\n" << printed;
    EXPECT_NE(printed.find("abort: gyrocal-sim-rig ended unexpectedly (killed by signal 9"),
              std::string::npos)
        << printed;

    Sql sql(dir + "/run.db");
    EXPECT_EQ(sql.Rows("PRAGMA integrity_check").at(0).at(0), "ok");
    const auto run = sql.Rows("SELECT run_id, outcome, reason FROM runs WHERE run_id <> ''").at(0);
    EXPECT_EQ(run.at(1), "abort");
    EXPECT_NE(run.at(2).find("simulated chamber and units went with it"), std::string::npos)
        << run.at(2);
    // The cause is where the user looks: `gyrocal show` prints the stored reason.
    launch::ChildProcess show({GYROCAL_CLI, "show", run.at(0), "--db", dir + "/run.db"},
                              dir + "/show.txt", dir + "/show.txt");
    ASSERT_TRUE(show.Wait(std::chrono::seconds(60)).has_value());
    EXPECT_NE(launch::ReadLog(dir + "/show.txt")
                  .find("gyrocal-sim-rig ended unexpectedly (killed by signal 9"),
              std::string::npos)
        << launch::ReadLog(dir + "/show.txt");
    // One abort: the sequencer ended on the supervisor's, without one of its own.
    EXPECT_EQ(sql.Int("SELECT count(*) FROM run_events WHERE event IN ('stop', 'abort')"), 1);
    EXPECT_EQ(launch::ReadLog(dir + "/logs/gyrocal-sequencer.log").find("operator stop"),
              std::string::npos);
    // Everything the rig published before it died was recorded: no gap in any stream.
    EXPECT_EQ(sql.Int("SELECT coalesce(sum(seq_gaps + queue_drops), 0) FROM losses"), 0);
    for (const auto& r :
         sql.Rows("SELECT count(*), max(seq) - min(seq) + 1 FROM gyro_samples GROUP BY sensor_id"))
        EXPECT_EQ(r[0], r[1]);
}

}  // namespace
}  // namespace gyrocal
