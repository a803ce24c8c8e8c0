// How fast gyrocal-sim-rig runs on LCM: starts the real process at several --speed values (4
// units, 100 Hz, encoder 100 Hz) on its own multicast port, receives everything here, and prints
// the achieved simulated speed, messages/s and samples lost (seq gaps). Not a test: figures.
// Run: <build>/bin/gyrocal_bench_sim_rig_bus [cap=MSGS_PER_S] [speed ...]
//      (default speeds 100 200 500 1000 2000; cap is passed as --max-msgs-per-s, default the rig's)
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/bench/support/bench_context.hpp"

namespace {}  // namespace

int main(int argc, char** argv) {
    std::vector<double> speeds = {100, 200, 500, 1000, 2000};
    std::string cap;
    std::vector<double> given;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("cap=", 0) == 0) {
            cap = a.substr(4);
        } else {
            given.push_back(std::stod(a));
        }
    }
    if (!given.empty()) speeds = given;
    const std::string url = "udpm://239.255.76.67:7729?ttl=0&recv_buf_size=4194304";
    const double wall_s = 5.0;
    gyrocal::bench::PrintContext(argc, argv);
    std::printf("--max-msgs-per-s %s\n", cap.empty() ? "(default)" : cap.c_str());
    std::printf("%8s %10s %12s %12s %10s %10s\n", "speed", "sim_s", "achieved_x", "msgs/s",
                "received", "lost");
    for (double speed : speeds) {
        gyrocal::bus::Bus bus(gyrocal::bus::BusOptions{url});
        int64_t received = 0, first_utime = -1, last_utime = -1;
        bus.Subscribe<gyrocal::gyro_sample_t>(
            gyrocal::channels::AllSensors(gyrocal::channels::kGyroPrefix),
            [&](const gyrocal::gyro_sample_t& m, const std::string&) {
                ++received;
                if (first_utime < 0) first_utime = m.utime;
                last_utime = m.utime;
            });
        bus.Subscribe<gyrocal::encoder_sample_t>(
            std::string(gyrocal::channels::kEncoder),
            [&](const gyrocal::encoder_sample_t&, const std::string&) { ++received; });
        const double duration_s = speed * wall_s;
        std::vector<std::string> argv_rig = {GYROCAL_SIM_RIG_EXE,
                                             "--lcm-url",
                                             url,
                                             "--speed",
                                             std::to_string(speed),
                                             "--duration-s",
                                             std::to_string(duration_s)};
        if (!cap.empty()) argv_rig.insert(argv_rig.end(), {"--max-msgs-per-s", cap});
        gyrocal::launch::ChildProcess rig(argv_rig, "/dev/null", "/dev/null");
        const auto t0 = std::chrono::steady_clock::now();
        while (!rig.Poll()) bus.Handle(std::chrono::milliseconds(10));
        while (bus.Handle(std::chrono::milliseconds(200))) {
        }
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double sim_s = (last_utime - first_utime) * 1e-6;
        std::printf("%8.0f %10.0f %12.1f %12.0f %10lld %10lld\n", speed, sim_s, sim_s / wall,
                    received / wall, static_cast<long long>(received),
                    static_cast<long long>(bus.counters().seq_gaps));
    }
    return 0;
}
