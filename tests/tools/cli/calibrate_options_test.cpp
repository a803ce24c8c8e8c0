// What `gyrocal calibrate` hands the fitter for the plateaus' slow noise: the simulated gyro type's
// characterisation for the simulated rig, nothing invented for measured data, the user's value
// whenever given; and a bad value is refused by the real CLI (exit 2, naming the option).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "producers/sim/config.hpp"
#include "producers/sim/gyro_facts.hpp"
#include "producers/sim/noise.hpp"
#include "tools/cli/cmd_calibrate.hpp"
#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::supervisor {
namespace {

TEST(CalibrateOptions, PlateauSlowNoiseIsTheSimulatedGyrosOnlyForTheRig) {
    CalibrateOptions o;
    // What `gyrocal calibrate --source sim` fills in from the rig's side (cmd_calibrate.cpp).
    const sim::SimulatedGyroFacts facts = sim::FactsOfSimulatedGyros("610");
    o.simulated = SimulatedGyros{facts.plateau_slow_noise_dps, facts.nominal_sensitivity_v_per_dps};
    // The rig's defaults (bias instability 0.008 deg/s, rate random walk 5e-5 deg/s/sqrt(s)) in a
    // 60 s mean: 0.0152 deg/s (sim::SlowNoiseBinVariance, checked there against 60 simulated
    // hours).
    EXPECT_NEAR(EffectivePlateauSlowNoiseDps(o), 0.0152, 0.0005);
    EXPECT_EQ(o.simulated.nominal_sensitivity_v_per_dps,
              sim::PresetByName("610").sensitivity_v_per_dps);
    EXPECT_DOUBLE_EQ(EffectivePlateauSlowNoiseDps(o),
                     std::sqrt(sim::SlowNoiseBinVariance(sim::NoiseConfig{}, 60.0, 3600.0)));
    o.source = "csv";  // measured data: none passed, the fitter uses the run's Allan deviation
    EXPECT_LT(EffectivePlateauSlowNoiseDps(o), 0.0);
    o.plateau_slow_noise_dps = 0.02;
    EXPECT_EQ(EffectivePlateauSlowNoiseDps(o), 0.02);
    o.source = "sim";
    o.plateau_slow_noise_dps = 0.0;
    EXPECT_EQ(EffectivePlateauSlowNoiseDps(o), 0.0);
}

// The children's pass-through lists (kChildArgs, which both the options and the run's
// configuration take them from): one entry per list of CalibrateOptions, and each given to
// `gyrocal calibrate` as --<name>-arg with the child named in the help.
TEST(CalibrateOptions, EachChildsPassThroughListIsOneEntryAndOneOption) {
    CalibrateOptions o;
    std::set<std::string> names;
    for (const ChildArgs& c : kChildArgs) {
        (o.*c.args).push_back(c.name);
        names.insert(c.name);
    }
    EXPECT_EQ(names.size(), 8u);
    for (const ChildArgs& c : kChildArgs)
        EXPECT_EQ(o.*c.args, std::vector<std::string>{c.name}) << "a list shared with another";
    EXPECT_EQ(o.source_args, std::vector<std::string>{"source"});
    const std::string out = ::testing::TempDir() + "gyrocal_cal_help_" + std::to_string(getpid());
    launch::ChildProcess p({GYROCAL_CLI, "calibrate", "--help"}, out, out);
    const auto st = p.Wait(std::chrono::seconds(10));
    ASSERT_TRUE(st.has_value() && st->exited && st->code == 0);
    const std::string help = launch::ReadLog(out);
    std::filesystem::remove(out);
    for (const ChildArgs& c : kChildArgs) {
        EXPECT_NE(help.find("--" + std::string(c.name) + "-arg"), std::string::npos) << c.name;
        EXPECT_NE(help.find(std::string("extra argument for ") + c.child), std::string::npos)
            << c.child;
    }
}

// Bad options of the real CLI: exit 2 with the option named, before any process starts; a child
// that refuses its options ends the start-up at once (exit 1 with its log), not after a heartbeat
// timeout. Port 7797, this file's own.
TEST(CalibrateOptions, BadOptionsAreRefusedBeforeOrAtStartUp) {
    using namespace std::chrono_literals;
    const std::string dir = ::testing::TempDir() + "gyrocal_cal_opts_" + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    const std::string db = dir + "/x.db", err = dir + "/err.txt";
    struct Case {
        std::vector<std::string> args;
        int code;
        std::string says;
    };
    const std::vector<Case> cases = {
        {{"--effect", "bogus=1"}, 2, "--effect 'bogus' is unknown; valid names:"},
        {{"--effect", "supply=abc"}, 2, "is not a number"},
        {{"--plateau-slow-noise-dps", "-1"}, 2, "--plateau-slow-noise-dps"},
        {{"--sensors", "0"}, 2, "--sensors"},
        {{"--profile", "seven"}, 2, "--profile"},
        {{"--source", "csv"}, 2, "--input"},
        {{"--rig-arg=--bogus"}, 1, "gyrocal-sim-rig ended at start-up (exit code 2)"},
        {{"--role", "hub"}, 2, "--role"},
        {{"--chamber", "0"}, 2, "--chamber"},
        {{"--chamber", "2", "--lcm-url", "memq://"}, 2, "--chamber 2 needs a udpm:// LCM URL"},
        {{"--chamber", "100", "--lcm-url", "udpm://239.255.76.67:65500?ttl=0"}, 2, "is past 65535"},
        {{"--procedure", "manual"}, 2, "--procedure"},
        {{"--procedure", "rig", "--source", "csv", "--input", "/etc/hostname"},
         2,
         "--procedure: rig is the simulated"},
        {{"--max-restarts", "21"}, 2, "--max-restarts"},
        // The producers of a multi-host lab whose other roles never came: a clear failure. On a
        // port of its own (7812): on 7797 another worktree's run of this test may start a recorder.
        {{"--role", "producers", "--await-peers-s", "1", "--lcm-url",
          "udpm://239.255.76.67:7812?ttl=0"},
         1,
         "no heartbeat from gyrocal-recorder within 1 s (start `gyrocal calibrate --role "
         "processors` and `--role "
         "recorder` on their hosts first"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> argv = {GYROCAL_CLI, "calibrate", "--db",       db,
                                         "--quiet",   "--log-dir", dir + "/logs"};
        if (std::find(c.args.begin(), c.args.end(), "--lcm-url") == c.args.end())
            argv.insert(argv.end(), {"--lcm-url", "udpm://239.255.76.67:7797?ttl=0"});
        argv.insert(argv.end(), c.args.begin(), c.args.end());
        launch::ChildProcess p(argv, "/dev/null", err);
        // The child's failure is seen within the start-up poll, far below the 20 s heartbeat wait.
        const auto st = p.Wait(15s);
        ASSERT_TRUE(st.has_value()) << c.args[0] << ": still running";
        EXPECT_TRUE(st->exited && st->code == c.code) << c.args[0] << ": " << st->Describe();
        EXPECT_NE(launch::ReadLog(err).find(c.says), std::string::npos) << launch::ReadLog(err);
    }
    std::filesystem::remove_all(dir);
}

// The supervisor takes what it needs of the store as a dependency (StoreServices), not from a
// global hook: a command built without an acceptance step refuses --limits and --report when the
// options are parsed, naming the option, and one given a step accepts them; nothing runs.
TEST(CalibrateOptions, LimitsAndReportNeedTheAcceptanceStepPassedIn) {
    const std::string dir = ::testing::TempDir() + "gyrocal_cal_svc_" + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    const std::string limits = dir + "/limits.json";
    std::ofstream(limits) << R"({"max_offset_change_dps": 25.0})";
    const std::string db = dir + "/x.db";
    for (const bool with_step : {false, true}) {
        for (const std::vector<std::string>& extra :
             {std::vector<std::string>{"--limits", limits}, {"--report", dir}}) {
            CLI::App app;
            std::function<int()> action;
            StoreServices services;
            if (with_step)
                services.after_run = [](const CalibrateOptions&, const std::string&, int code) {
                    return code;
                };
            cli::AddCalibrateCommand(app, action, services);
            std::vector<std::string> args = {"gyrocal", "calibrate", "--db", db};
            args.insert(args.end(), extra.begin(), extra.end());
            std::vector<const char*> argv;
            for (const std::string& a : args) argv.push_back(a.c_str());
            if (with_step) {
                EXPECT_NO_THROW(app.parse(static_cast<int>(argv.size()), argv.data())) << extra[0];
                EXPECT_TRUE(static_cast<bool>(action)) << extra[0];
                continue;
            }
            try {
                app.parse(static_cast<int>(argv.size()), argv.data());
                ADD_FAILURE() << extra[0] << " accepted without an acceptance step";
            } catch (const CLI::ValidationError& e) {
                EXPECT_NE(std::string(e.what()).find(extra[0]), std::string::npos) << e.what();
                EXPECT_NE(std::string(e.what()).find("needs the store"), std::string::npos)
                    << e.what();
            }
            EXPECT_FALSE(static_cast<bool>(action));
        }
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal::supervisor
