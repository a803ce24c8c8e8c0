#include "tests/producers/producer_process_support.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::test {

std::string UdpmUrl(int port) {
    return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304";
}

std::string Bin(const std::string& name) { return std::string(GYROCAL_BIN_DIR) + "/" + name; }

Scratch::Scratch(const std::string& name)
    : dir_(std::filesystem::temp_directory_path() /
           ("gyrocal_sources_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
}

Scratch::~Scratch() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
}

std::vector<std::string> WriteSyntheticCsv(const std::string& path, const SyntheticSpec& spec) {
    std::mt19937 rng(spec.seed);
    std::normal_distribution<double> gyro_noise(0.0, 0.002);
    std::normal_distribution<double> temp_noise(0.0, 0.0005);
    std::vector<std::string> lines;
    const int n = static_cast<int>(std::lround(spec.duration_s * spec.rate_hz));
    for (int i = 0; i < n; ++i) {
        const double t = i / spec.rate_hz;
        // 90 deg in 0.5 s with a smooth (cosine) profile, then at rest.
        const double u = std::clamp((t - 1.0) / 0.5, 0.0, 1.0);
        const double angle_deg = 90.0 * (1.0 - std::cos(M_PI * u)) / 2.0;
        const double chamber_c = 25.0 + 0.5 * std::floor(t);
        for (size_t k = 0; k < spec.sensors.size(); ++k) {
            const double temp_c = 25.0 + 1.0 * t + 0.3 * k;
            char supply[32] = "";
            if (k + 1 < spec.sensors.size())
                std::snprintf(supply, sizeof supply, "%.6f", 5.0 + 0.01 * k);
            char buf[256];
            std::snprintf(buf, sizeof buf, "op%zu,%s,%.6f,%.6f,%.6f,%s,%.6f,%.3f", k,
                          spec.sensors[k].c_str(), t,
                          2.5 + 0.009 * (temp_c - 25.0) + temp_noise(rng),
                          2.5 + 0.01 * k + gyro_noise(rng), supply, angle_deg, chamber_c);
            lines.emplace_back(buf);
        }
    }
    std::ostringstream text;
    text << kSyntheticHeader << "\n";
    for (const std::string& l : lines) text << l << "\n";
    WriteText(path, text.str());
    return lines;
}

csv::CsvFile ReadCsvFile(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    return csv::ReadCsv(in, path, sensor::TempTransfer{}, csv::OnError::kStop);
}

std::string Slurp(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
}

void WriteGoodAndBad(const Scratch& dir, const std::string& bad_file,
                     const std::map<size_t, std::string>& inserted) {
    const std::vector<std::string> lines = WriteSyntheticCsv(dir.Path("good.csv"), SyntheticSpec{});
    std::string text = std::string(kSyntheticHeader) + "\n";
    for (size_t i = 0; i < lines.size(); ++i) {
        text += lines[i] + "\n";
        if (const auto it = inserted.find(i); it != inserted.end()) text += it->second + "\n";
    }
    WriteText(dir.Path(bad_file), text);
}

void WriteText(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
}

launch::ChildProcess StartCsvRecord(const Scratch& dir, const std::string& url,
                                    const std::string& out, const std::string& err,
                                    const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {
        Bin("gyrocal-csv-record"), "--out", dir.Path(out), "--lcm-url", url, "--idle-exit-s", "3"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return launch::ChildProcess(argv, "", dir.Path(err));
}

launch::ChildProcess StartCsvSource(const Scratch& dir, const std::string& url,
                                    const std::string& csv, const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {Bin("gyrocal-csv-source"), dir.Path(csv), "--lcm-url", url};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return launch::ChildProcess(argv, "", dir.Path("source.err"));
}

bool WaitForStatus(const std::string& url, const std::vector<const launch::ChildProcess*>& children,
                   std::chrono::milliseconds timeout) {
    bus::Bus bus(bus::BusOptions{url});
    std::set<int32_t> waiting;
    for (const launch::ChildProcess* c : children) waiting.insert(static_cast<int32_t>(c->pid()));
    bus.Subscribe<status_t>(std::string(channels::kStatus),
                            [&](const status_t& s, const std::string&) { waiting.erase(s.pid); });
    return testing::HandleUntil(
        bus, [&] { return waiting.empty(); }, timeout);
}

launch::ExitStatus WaitExit(launch::ChildProcess& child, std::chrono::milliseconds timeout) {
    if (auto s = child.Wait(timeout)) return *s;
    ADD_FAILURE() << child.name() << " still running after " << timeout.count() << " ms";
    return child.Stop();
}

void ExpectSameSamples(const csv::CsvFile& original, const csv::CsvFile& recorded,
                       const std::vector<std::string>& sensors) {
    auto wanted = [&](const std::string& id) {
        return sensors.empty() || std::find(sensors.begin(), sensors.end(), id) != sensors.end();
    };
    std::map<std::string, std::vector<const csv::CsvRow*>> a, b;
    for (const auto& r : original.rows) {
        if (wanted(r.sensor_id)) a[r.sensor_id].push_back(&r);
    }
    for (const auto& r : recorded.rows) b[r.sensor_id].push_back(&r);
    ASSERT_EQ(a.size(), b.size()) << "sensors differ";
    for (const auto& [id, rows] : a) {
        const auto& got = b[id];
        ASSERT_EQ(got.size(), rows.size()) << "sample count of " << id;
        for (size_t i = 0; i < rows.size(); ++i) {
            const csv::CsvRow& x = *rows[i];
            const csv::CsvRow& y = *got[i];
            SCOPED_TRACE(id + " sample " + std::to_string(i) + " (original line " +
                         std::to_string(x.line) + ")");
            ASSERT_EQ(csv::TimeUs(y.time_s), csv::TimeUs(x.time_s));
            EXPECT_EQ(y.gyro_v, x.gyro_v);
            EXPECT_EQ(y.temp_v, x.temp_v);
            // Same formula, same double operations: bit-identical.
            EXPECT_EQ(y.temp_c, 25.0 + (x.temp_v - 2.5) / 0.009);
            EXPECT_EQ(y.supply_v, x.supply_v);
            EXPECT_EQ(y.encoder_deg, x.encoder_deg);
            EXPECT_EQ(y.chamber_c, x.chamber_c);
        }
    }
}

}  // namespace gyrocal::test
