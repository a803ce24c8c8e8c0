// gyrocal-plateau and gyrocal-rotation on the real simulated rig (gyrocal-sim-rig --mode builtin),
// all three as OS processes over UDP multicast (port 7742), checked against the rig's truth
// sidecar: plateaus only once the DIE has settled, plateau offsets and rotation sensitivities on
// the truth curves, both directions, at every setpoint.
//
// The rig is made quick: one unit, package lag 100 s (instead of 200), 700 s dwell, 10 s rest
// after each move, setpoints 10 and 40 degC: ~2400 simulated seconds, ~16 s of wall time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "gyrocal/plateau_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "producers/sim/noise.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7742?ttl=0&recv_buf_size=4194304";

bool WaitFor(bus::Bus& bus, const std::function<bool()>& done, std::chrono::milliseconds limit) {
    return testing::HandleUntil(bus, done, limit, std::chrono::milliseconds(20));
}

// y = sum c_i dT^i for the truth's {1, dT, dT^2} curves.
double Curve(const nlohmann::json& model, double temp_c) {
    const double dt = temp_c - model.at("t0_c").get<double>();
    double y = 0, p = 1;
    for (const auto& c : model.at("coeffs")) {
        y += c.get<double>() * p;
        p *= dt;
    }
    return y;
}

// Standard deviation [deg/s] of the mean over a window of w_s seconds of the rig's bias
// instability alone (sim::SlowNoiseBinVariance with the other noise off): the slow components are
// hardly averaged by a 60 s window, so this is the part of a plateau's error that no
// within-window SEM can see.
double BiasInstabilityOfMeanDps(double level_dps, double w_s) {
    sim::NoiseConfig nc;
    nc.bias_instability_dps = level_dps;
    nc.rate_random_walk_dps_rts = 0.0;
    return std::sqrt(sim::SlowNoiseBinVariance(nc, w_s, 0.0));
}

TEST(RigPipeline, PlateausAndSensitivitiesMatchTheRigTruth) {
    bus::Bus bus(bus::BusOptions{kUrl});
    std::vector<plateau_t> plateaus;
    std::vector<sensitivity_point_t> points;
    std::map<std::string, bool> up;
    testing::CollectInto(bus, channels::AllSensors(channels::kPlateauPrefix), plateaus);
    testing::CollectInto(bus, channels::AllSensors(channels::kSensitivityPrefix), points);
    bus.Subscribe<status_t>(std::string(channels::kStatus),
                            [&](const status_t& m, const std::string&) { up[m.process] = true; });
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gyrocal_rig_pipeline_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    auto out = [&](const std::string& name) { return (dir / name).string(); };
    launch::ChildProcess plateau({GYROCAL_PLATEAU_BIN, "--lcm-url", kUrl}, out("plateau.out"),
                                 out("plateau.err"));
    launch::ChildProcess rotation({GYROCAL_ROTATION_BIN, "--lcm-url", kUrl}, out("rotation.out"),
                                  out("rotation.err"));
    ASSERT_TRUE(WaitFor(
        bus, [&] { return up["gyrocal-plateau"] && up["gyrocal-rotation"]; },
        std::chrono::seconds(10)));
    const std::vector<double> setpoints{10.0, 40.0};
    launch::ChildProcess rig({GYROCAL_SIM_RIG_BIN,
                              "--lcm-url",
                              kUrl,
                              "--mode",
                              "builtin",
                              "--units",
                              "1",
                              "--seed",
                              "5",
                              "--profile",
                              "10,40",
                              "--dwell-s",
                              "700",
                              "--rest-s",
                              "10",
                              "--package-tau-s",
                              "100",
                              "--package-tau-spread",
                              "0",
                              "--speed",
                              "1000",
                              "--truth-out",
                              out("truth.json")},
                             out("rig.out"), out("rig.err"));
    const auto rig_end = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    std::optional<launch::ExitStatus> rig_status;
    while (!(rig_status = rig.Poll()) && std::chrono::steady_clock::now() < rig_end)
        bus.Handle(std::chrono::milliseconds(20));
    ASSERT_TRUE(rig_status && rig_status->exited && rig_status->code == 0)
        << (rig_status ? rig_status->Describe() : "rig still running after 90 s");
    WaitFor(
        bus, [&] { return points.size() >= 4; }, std::chrono::seconds(5));
    EXPECT_EQ(plateau.Stop().code, 0);
    EXPECT_EQ(rotation.Stop().code, 0);

    const nlohmann::json truth = nlohmann::json::parse(std::ifstream(out("truth.json")));
    const nlohmann::json& unit = truth.at("units").at(0);
    const double sensor_offset_c = unit.at("temp_sensor_offset_c").get<double>();
    const double tau_die_s = unit.at("package_tau_s").get<double>();

    // One plateau per setpoint (the one at the power-on 25 degC comes first, before any order).
    std::map<double, plateau_t> by_setpoint;
    for (const plateau_t& p : plateaus) by_setpoint[p.setpoint_c] = p;
    for (double sp : setpoints) {
        SCOPED_TRACE("setpoint " + std::to_string(sp));
        ASSERT_EQ(by_setpoint.count(sp), 1u);
        const plateau_t& p = by_setpoint.at(sp);
        EXPECT_EQ(std::count_if(plateaus.begin(), plateaus.end(),
                                [&](const plateau_t& q) { return q.setpoint_c == sp; }),
                  1);
        // The die: temp_c minus the unit's sensor offset (the sensor's own lag adds at most
        // slope * 15 s = 0.0125 degC on a plateau). With the air at the setpoint the die's
        // distance to it is tau_die * |die slope| <= tau_die * (0.05 + 3 SE) degC/min; the
        // window mean is closer still. 3 SE at the rig's 0.035 degC scatter over 90 s is
        // 0.0026 degC/min; the air's own control noise (0.02 degC) gives another 0.06 at 3 sigma.
        const double die_c = p.temp_mean_c - sensor_offset_c;
        const double bound_c = tau_die_s * (0.05 + 0.0026) / 60.0 + 0.0125 + 0.06;
        std::printf(
            "plateau sp %5.1f: die %.4f degC (bound %.3f), offset %.6f V vs truth %.6f (%.2f SEM; "
            "bias instability of the mean %.2e V)\n",
            sp, die_c, bound_c, p.gyro_mean_v, Curve(unit.at("offset_v"), die_c),
            (p.gyro_mean_v - Curve(unit.at("offset_v"), die_c)) / p.gyro_sem_v,
            BiasInstabilityOfMeanDps(0.008, 60.0) * 0.006);
        EXPECT_NEAR(die_c, sp, bound_c);
        // The offset on the truth curve at that die temperature: 4 sigma, sigma = the reported
        // SEM (white and short-correlated noise) and the rig's bias instability (0.008 deg/s,
        // times the sensitivity) over the 60 s window in quadrature; plus the curve's slope
        // (< 1 mV/K) times the die-temperature error of 0.0125 degC.
        const double bi_v = BiasInstabilityOfMeanDps(0.008, 60.0) * 0.006;
        const double sigma_v = std::hypot(p.gyro_sem_v, bi_v);
        EXPECT_NEAR(p.gyro_mean_v, Curve(unit.at("offset_v"), die_c), 4 * sigma_v + 1.25e-5);
    }
    // Two rotations per setpoint, + then -, each on the truth curve within 4 reported sigma
    // (the curve's slope, < 1e-6 V/(deg/s)/K, times 0.1 degC is negligible). A point refused
    // for network loss (sequence gaps, possible on a loaded host) is allowed but must say so.
    int accepted = 0;
    for (double sp : setpoints) {
        std::vector<sensitivity_point_t> at;
        for (const sensitivity_point_t& q : points)
            if (std::fabs(q.temp_c - sensor_offset_c - sp) < 1.0) at.push_back(q);
        SCOPED_TRACE("setpoint " + std::to_string(sp));
        ASSERT_EQ(at.size(), 2u);
        EXPECT_EQ(at[0].direction, 1);
        EXPECT_EQ(at[1].direction, -1);
        for (const sensitivity_point_t& q : at) {
            if (!q.accepted) {
                EXPECT_NE(q.reject_reason.find("sequence gaps"), std::string::npos)
                    << q.reject_reason;
                continue;
            }
            ++accepted;
            const double s_true =
                Curve(unit.at("sensitivity_v_per_dps"), q.temp_c - sensor_offset_c);
            std::printf("rotation sp %5.1f dir %+d: S %.7f vs truth %.7f V/(deg/s) (z = %.2f)\n",
                        sp, q.direction, q.sensitivity_v_per_dps, s_true,
                        (q.sensitivity_v_per_dps - s_true) / q.sensitivity_stderr_v_per_dps);
            EXPECT_NEAR(q.sensitivity_v_per_dps,
                        Curve(unit.at("sensitivity_v_per_dps"), q.temp_c - sensor_offset_c),
                        4 * q.sensitivity_stderr_v_per_dps);
            EXPECT_NEAR(std::fabs(q.encoder_angle_deg), 90.0, 360.0 / 10000);
        }
    }
    EXPECT_GE(accepted, 2);
    if (!HasFailure()) std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
