#pragma once
// The stored run that gyrocal-replay's tests publish back (replay_process_test.cpp, the process;
// replay_node_test.cpp, its node in-process): run "RR" of units A and B, kSamples gyro samples
// each and as many encoder readings over kSpanUs of reception time, one chamber state, start and
// stop events.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/writer.hpp"

namespace gyrocal::testing {

inline constexpr int64_t kSpanUs = 2000000;  // recorded span: 2 s
inline constexpr int64_t kSamples = 400;     // per sensor, evenly over the span

inline void WriteSourceRun(const std::string& path) {
    db::StoreWriter w(path, {"t", "h", 1});
    std::vector<db::Row> rows;
    db::RunEventRow start;
    start.run_id = "RR";
    start.event = "start";
    start.utime = 1;
    start.sensor_ids = {"A", "B"};
    start.setpoint_c = std::nan("");
    start.config_json = R"({"k":1})";
    start.recv_utime = 0;
    rows.push_back(start);
    for (int64_t i = 0; i < kSamples; ++i) {
        for (const char* id : {"A", "B"}) {
            db::GyroRow g;
            g.run_id = "RR";
            g.sensor_id = id;
            g.seq = i;
            g.utime = 1000000000000000 + i * 5000;
            g.gyro_v = 2.5 + 1e-6 * static_cast<double>(i);
            g.temp_c = 25;
            g.supply_v = std::nan("");
            g.supply_counts = -1;
            g.recv_utime = 1 + i * kSpanUs / kSamples;
            rows.push_back(g);
        }
        db::EncoderRow e;
        e.run_id = "RR";
        e.encoder_id = "TABLE";
        e.seq = i;
        e.utime = 1000000000000000 + i * 5000;
        e.counts = i;
        e.recv_utime = 1 + i * kSpanUs / kSamples;
        rows.push_back(e);
    }
    db::ChamberStateRow c;
    c.run_id = "RR";
    c.utime = 5;
    c.recv_utime = kSpanUs / 2;
    rows.push_back(c);
    db::RunEventRow stop = start;
    stop.event = "stop";
    stop.recv_utime = kSpanUs;
    rows.push_back(stop);
    w.Write(rows, {});
}

}  // namespace gyrocal::testing
