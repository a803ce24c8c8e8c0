#include "tests/bench/compensator/latency_run.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>

#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "processors/compensator/compensate.hpp"
#include "tests/bench/support/machine.hpp"

namespace gyrocal::bench {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
constexpr const char* kCompensator = "gyrocal-compensator";

// [us] of the steady clock: the utime the sender stamps and the receiver compares with (one
// process, one clock). The truncation to whole us adds at most 1 us to a latency.
int64_t Micros(Clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
}

class Run {
public:
    explicit Run(const LatencyCase& c);
    LatencyResult Go();

private:
    void OnRate(const rate_t& m);
    void OnStatus(const status_t& m);
    double StatusExtra(const std::string& name) const;
    template <class F>
    bool WaitFor(F&& done, std::chrono::seconds timeout);
    void Require(bool ok, const std::string& what);
    void Start();
    void Send();
    void Receive();
    void Verify();

    const LatencyCase c_;
    const int64_t per_sensor_;  // [count] samples per sensor
    std::vector<std::string> ids_, gyro_channels_;
    std::map<std::string, int> index_;
    std::vector<model::CoeffSet> sets_;
    std::vector<std::vector<RawSample>> streams_;
    std::vector<std::vector<int64_t>> sent_utime_;  // [us] per sensor and seq; -1 = not sent
    std::vector<std::vector<double>> rate_dps_;     // received, per sensor and seq
    std::vector<std::vector<char>> got_;            // a rate was received
    std::vector<std::vector<int64_t>> rate_utime_;  // [us] the received rate's utime
    std::vector<double> latency_us_;
    bus::Bus rx_;
    std::optional<launch::ChildProcess> comp_;
    std::optional<status_t> status_;
    int64_t power_on_utime_ = 0;
    std::atomic<int64_t> sent_{0};
    std::atomic<bool> sending_{false}, stop_{false};
    LatencyResult r_;
};

Run::Run(const LatencyCase& c)
    : c_(c),
      per_sensor_(static_cast<int64_t>(std::llround(c.duration_s * c.rate_hz))),
      rx_(bus::BusOptions{c.lcm_url}) {
    for (int i = 0; i < c_.sensors; ++i) {
        char id[16];
        std::snprintf(id, sizeof id, "B%02d", i + 1);
        ids_.push_back(id);
        gyro_channels_.push_back(channels::Gyro(id));
        index_[id] = i;
        sets_.push_back(BenchSet(c_.model, id));
        streams_.push_back(SyntheticStream(i, c_.rate_hz, per_sensor_));
    }
    const size_t n = static_cast<size_t>(per_sensor_);
    sent_utime_.assign(ids_.size(), std::vector<int64_t>(n, -1));
    rate_dps_.assign(ids_.size(), std::vector<double>(n, 0.0));
    got_.assign(ids_.size(), std::vector<char>(n, 0));
    rate_utime_.assign(ids_.size(), std::vector<int64_t>(n, -1));
    latency_us_.reserve(n * ids_.size());
    rx_.Subscribe<rate_t>(channels::AllSensors(channels::kRatePrefix),
                          [this](const rate_t& m, const std::string&) { OnRate(m); });
    rx_.Subscribe<status_t>(std::string(channels::kStatus),
                            [this](const status_t& m, const std::string&) { OnStatus(m); });
}

void Run::OnRate(const rate_t& m) {
    const double now_us =
        1e-3 * static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                       Clock::now().time_since_epoch())
                                       .count());
    const auto it = index_.find(m.sensor_id);
    if (it == index_.end() || m.seq < 0 || m.seq >= per_sensor_) {
        ++r_.stray;
        return;
    }
    const auto i = static_cast<size_t>(it->second), k = static_cast<size_t>(m.seq);
    if (got_[i][k]) {
        ++r_.stray;
        return;
    }
    got_[i][k] = 1;
    rate_dps_[i][k] = m.rate_dps;
    rate_utime_[i][k] = m.utime;
    latency_us_.push_back(now_us - static_cast<double>(m.utime));
    ++r_.received;
}

void Run::OnStatus(const status_t& m) {
    if (m.process == kCompensator && comp_ && m.pid == comp_->pid()) status_ = m;
}

double Run::StatusExtra(const std::string& name) const {
    for (size_t i = 0; status_ && i < status_->extra_names.size(); ++i)
        if (status_->extra_names[i] == name) return status_->extra_values[i];
    return NAN;
}

template <class F>
bool Run::WaitFor(F&& done, std::chrono::seconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (!done()) {
        if (Clock::now() > deadline || comp_->Poll()) return false;
        rx_.Handle(50ms);
    }
    return true;
}

void Run::Require(bool ok, const std::string& what) {
    if (ok) return;
    std::string why = "gyrocal-compensator: " + what;
    if (comp_) {
        if (auto st = comp_->Poll()) why += " (it ended: " + st->Describe() + ")";
    }
    throw std::runtime_error(why + "; its log: " + c_.log_path);
}

void Run::Start() {
    comp_.emplace(std::vector<std::string>{c_.compensator_exe, "--lcm-url", c_.lcm_url},
                  c_.log_path, c_.log_path);
    // Generous bounds: a loaded 2-core machine may take seconds to start a process.
    Require(WaitFor([&] { return status_.has_value(); }, 30s), "no STATUS within 30 s");
    power_on_utime_ = Micros(Clock::now());
    for (size_t i = 0; i < ids_.size(); ++i) {
        power_state_t p{};
        p.utime = power_on_utime_;
        p.sensor_id = ids_[i];
        p.power_on_utime = power_on_utime_;
        p.source = "bench";
        rx_.Publish(channels::Power(ids_[i]), p);
        rx_.Publish(channels::Coeffs(ids_[i]), model::ToMsg(sets_[i]));
    }
    Require(WaitFor([&] { return StatusExtra("coeff_sets_applied") >= c_.sensors; }, 30s),
            "did not apply the " + std::to_string(c_.sensors) + " coefficient sets within 30 s");
}

// The sender thread: sample k of sensor i is due at (k + i / N) / R s after the start, so the
// sensors are spread evenly over each period; a late sender publishes at once (its lateness is
// reported) and every sample is stamped when it is published.
void Run::Send() {
    bus::Bus tx(bus::BusOptions{c_.lcm_url});
    const int n = c_.sensors;
    const double step_ns = 1e9 / (c_.rate_hz * n);
    std::vector<int64_t> last(ids_.size(), 0);
    gyro_sample_t m{};
    m.supply_counts = -1;
    Clock::duration behind{};
    const Clock::time_point t0 = Clock::now();
    for (int64_t j = 0; j < per_sensor_ * n && !stop_; ++j) {
        const auto i = static_cast<size_t>(j % n);
        const int64_t k = j / n;
        const Clock::time_point due = t0 + std::chrono::nanoseconds(std::llround(j * step_ns));
        Clock::time_point now = Clock::now();
        if (now < due) {
            std::this_thread::sleep_until(due);
            now = Clock::now();
        }
        behind = std::max(behind, now - due);
        // utime must increase per sensor (the compensator refuses a repeat)
        const int64_t utime = std::max(Micros(now), last[i] + 1);
        const RawSample& x = streams_[i][static_cast<size_t>(k)];
        m.utime = utime;
        m.sensor_id = ids_[i];
        m.seq = k;
        m.gyro_v = x.gyro_v;
        m.temp_c = x.temp_c;
        m.temp_v = 2.5 + 0.009 * (x.temp_c - 25.0);  // ADXRS61x: 2.5 V at 25 degC, 9 mV/K
        m.supply_v = x.supply_v;
        if (!tx.Publish(gyro_channels_[i], m)) continue;
        last[i] = utime;
        sent_utime_[i][static_cast<size_t>(k)] = utime;
        sent_.fetch_add(1, std::memory_order_release);
    }
    r_.send_wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    r_.behind_max_ms = std::chrono::duration<double, std::milli>(behind).count();
    sending_ = false;
}

// Main thread: only dispatches the receiving bus, so a rate is timed when a subscriber sees it.
void Run::Receive() {
    sending_ = true;
    std::thread sender([this] { Send(); });
    try {
        while (sending_) {
            rx_.Handle(20ms);
            if (comp_->Poll()) stop_ = true;
        }
    } catch (...) {
        stop_ = true;
        sender.join();
        throw;
    }
    sender.join();
    r_.sent = sent_.load(std::memory_order_acquire);
    // Drain: until every rate is in or nothing has come for 5 s.
    auto last_progress = Clock::now();
    while (r_.received < r_.sent && Clock::now() - last_progress < 5s) {
        if (rx_.Handle(50ms)) last_progress = Clock::now();
    }
    r_.lost = r_.sent - r_.received;
}

// After the run (the sender's records are complete): the same library in this process, fed the
// same samples with the same power-on time, must give the same rates bit for bit (one
// arithmetic, no clock in it), each carrying its sample's utime.
void Run::Verify() {
    for (size_t i = 0; i < ids_.size(); ++i) {
        compensator::SensorCompensator comp;
        comp.SetCoefficients(sets_[i]);
        comp.PowerOn(power_on_utime_);
        bool in_step = true;
        for (size_t k = 0; k < static_cast<size_t>(per_sensor_); ++k) {
            if (sent_utime_[i][k] < 0) continue;  // never published: the compensator did not see it
            const RawSample& x = streams_[i][k];
            const compensator::ApplyResult a = comp.Apply(
                {sent_utime_[i][k], static_cast<int64_t>(k), x.gyro_v, x.temp_c, x.supply_v});
            if (!got_[i][k]) {
                in_step = false;
                continue;
            }
            if (!in_step) {
                ++r_.unchecked;
                continue;
            }
            ++r_.checked;
            if (a.status != compensator::ApplyStatus::kOk || a.out.rate_dps != rate_dps_[i][k] ||
                rate_utime_[i][k] != sent_utime_[i][k])
                ++r_.mismatched;
        }
    }
}

LatencyResult Run::Go() {
    r_.load_before = LoadAverage();
    Start();
    const double cpu0 = ReadProcStats(comp_->pid()).cpu_s;
    Receive();
    Require(!comp_->Poll().has_value(), "ended during the run");
    const ProcStats after = ReadProcStats(comp_->pid());
    r_.comp_cpu_s = after.cpu_s - cpu0;
    r_.comp_hwm_kb = after.hwm_kb;
    r_.load_after = LoadAverage();
    // Its next heartbeat (once a second) counts every sample it got; refusals are in it.
    if (WaitFor([&] { return StatusExtra("compensated") >= static_cast<double>(r_.received); }, 5s))
        r_.comp_rejected = status_->rejected;
    comp_->Stop();
    Verify();
    r_.latency = Summarize(std::move(latency_us_));
    return r_;
}

}  // namespace

LatencyResult RunLatencyCase(const LatencyCase& c) { return Run(c).Go(); }

}  // namespace gyrocal::bench
