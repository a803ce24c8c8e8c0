#include "tools/cli/run_loader.hpp"

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <variant>

#include "store/db/replay_reader.hpp"

namespace gyrocal::cli {

namespace an = gyrocal::analysis;
namespace st = gyrocal::db;

namespace {

// The run's recorded rows in their order, each handed on as the analysis reads it: gyro samples
// and power records of the `wanted` sensors (the others are passed over), every encoder reading
// and chamber air reading.
template <class OnGyro, class OnEncoder, class OnAir, class OnPower>
void ReadRun(st::Db& db, const std::string& run_id, const std::set<std::string>& wanted,
             OnGyro on_gyro, OnEncoder on_encoder, OnAir on_air, OnPower on_power) {
    st::ReplayReader reader(db, run_id, st::ReplayReader::GyroColumns::kAnalysis);
    while (auto row = reader.Next()) {
        std::visit(
            [&](const auto& r) {
                using T = std::decay_t<decltype(r)>;
                if constexpr (std::is_same_v<T, st::GyroRow>) {
                    if (wanted.count(r.sensor_id)) on_gyro(r.sensor_id, motion::GyroSampleOf(r));
                } else if constexpr (std::is_same_v<T, st::EncoderRow>) {
                    on_encoder(motion::EncoderReading{r.utime, r.counts, r.counts_per_rev});
                } else if constexpr (std::is_same_v<T, st::ChamberStateRow>) {
                    on_air(an::AirSample{r.utime, r.air_c});
                } else if constexpr (std::is_same_v<T, st::PowerStateRow>) {
                    if (wanted.count(r.sensor_id))
                        on_power(r.sensor_id, an::PowerRecord{r.utime, r.power_on_utime, r.source});
                }
            },
            *row);
    }
}

an::PlateauInput PlateauOf(const st::PlateauRow& p) {
    return {p.plateau_id, p.start_utime, p.end_utime,  p.temp_mean_c,
            p.temp_sem_c, p.gyro_mean_v, p.gyro_sem_v, p.n_samples};
}

an::SensitivityInput SensitivityOf(const st::SensitivityRow& s) {
    return {s.rotation_id,
            s.utime,
            s.temp_c,
            s.direction,
            s.sensitivity_v_per_dps,
            s.sensitivity_stderr_v_per_dps,
            s.accepted};
}

}  // namespace

std::map<std::string, an::SensorRun> LoadSensorRuns(st::Db& db, const st::RunDetail& detail,
                                                    const std::vector<std::string>& sensors) {
    const std::set<std::string> wanted(sensors.begin(), sensors.end());
    std::map<std::string, std::vector<an::GyroSample>> gyro;
    std::map<std::string, std::vector<an::PowerRecord>> power;
    std::vector<motion::EncoderReading> encoder;
    std::vector<an::AirSample> air;  // one chamber per run: every unit sat in the same air
    ReadRun(
        db, detail.run.run_id, wanted,
        [&](const std::string& id, const an::GyroSample& s) { gyro[id].push_back(s); },
        [&](const motion::EncoderReading& e) { encoder.push_back(e); },
        [&](const an::AirSample& a) { air.push_back(a); },
        [&](const std::string& id, const an::PowerRecord& p) { power[id].push_back(p); });
    std::map<std::string, an::SensorRun> runs;
    for (const std::string& id : sensors) {
        std::vector<an::PlateauInput> plateaus;
        for (const st::PlateauRow& p : detail.plateaus)
            if (p.sensor_id == id) plateaus.push_back(PlateauOf(p));
        std::vector<an::SensitivityInput> sens;
        for (const st::SensitivityRow& s : detail.sensitivity_points)
            if (s.sensor_id == id) sens.push_back(SensitivityOf(s));
        runs[id] = an::BuildSensorRun(id, std::move(gyro[id]), encoder, std::move(plateaus),
                                      std::move(sens), power[id]);
        an::AddChamberAir(runs[id], air);
    }
    return runs;
}

namespace {

// What the reader hands a shard: a wanted unit's sample or power record (`id` points into the
// sensors list, which outlives the shards), or an encoder or air reading (every shard's).
struct GyroEvent {
    const std::string* id;
    an::GyroSample s;
};
struct PowerEvent {
    const std::string* id;
    an::PowerRecord p;
};
using Event = std::variant<GyroEvent, motion::EncoderReading, an::AirSample, PowerEvent>;
using Batch = std::vector<Event>;

// A bounded queue of batches from the reader to one shard; an empty batch ends it. Close() lets
// either side stop the other after an error.
class BatchQueue {
public:
    bool Push(Batch b) {
        std::unique_lock<std::mutex> lock(mu_);
        cv_.wait(lock, [&] { return closed_ || q_.size() < kMaxBatches; });
        if (closed_) return false;
        q_.push_back(std::move(b));
        cv_.notify_all();
        return true;
    }
    std::optional<Batch> Pop() {
        std::unique_lock<std::mutex> lock(mu_);
        cv_.wait(lock, [&] { return closed_ || !q_.empty(); });
        if (q_.empty()) return std::nullopt;
        Batch b = std::move(q_.front());
        q_.pop_front();
        cv_.notify_all();
        return b;
    }
    void Close() {
        std::lock_guard<std::mutex> lock(mu_);
        closed_ = true;
        cv_.notify_all();
    }

private:
    static constexpr size_t kMaxBatches = 8;  // ~8 x 4096 events in flight per shard
    std::mutex mu_;
    std::condition_variable cv_;
    std::deque<Batch> q_;
    bool closed_ = false;
};

void Apply(an::RunBinner& b, const Event& e) {
    if (const auto* g = std::get_if<GyroEvent>(&e)) return b.AddGyro(*g->id, g->s);
    if (const auto* r = std::get_if<motion::EncoderReading>(&e)) return b.AddEncoder(*r);
    if (const auto* a = std::get_if<an::AirSample>(&e)) return b.AddAir(*a);
    const auto& p = std::get<PowerEvent>(e);
    b.AddPower(*p.id, p.p);
}

}  // namespace

// Reading and binning split over threads: this thread reads the rows (SQLite stepping is about
// half the work), and kShards threads each bin a share of the units, every shard fed the whole
// encoder and air stream in the run's order. A unit's bins depend only on its own samples, the
// encoder and the air, in that order, so each unit is binned exactly as one binner would.
analysis::RunBinner LoadBinnedRun(db::Db& db, const st::RunDetail& detail,
                                  const std::vector<std::string>& sensors,
                                  const analysis::IncrementalOptions& options) {
    constexpr size_t kShards = 2, kBatch = 4096;
    const std::set<std::string> wanted(sensors.begin(), sensors.end());
    std::map<std::string, std::pair<size_t, const std::string*>> shard_of;
    for (size_t i = 0; i < sensors.size(); ++i)
        shard_of.emplace(sensors[i], std::pair(i % kShards, &sensors[i]));
    std::vector<an::RunBinner> shards;
    for (size_t k = 0; k < kShards; ++k) shards.emplace_back(options);
    std::vector<BatchQueue> queues(kShards);
    std::vector<std::exception_ptr> errors(kShards + 1);
    std::vector<std::thread> workers;
    for (size_t k = 0; k < kShards; ++k)
        workers.emplace_back([&, k] {
            try {
                while (std::optional<Batch> b = queues[k].Pop()) {
                    if (b->empty()) break;
                    for (const Event& e : *b) Apply(shards[k], e);
                }
                shards[k].Flush();
            } catch (...) {
                errors[k] = std::current_exception();
                queues[k].Close();
            }
        });
    std::vector<Batch> open(kShards);
    auto send = [&](size_t k) {
        if (!queues[k].Push(std::move(open[k]))) throw std::runtime_error("binning stopped");
        open[k] = Batch();
        open[k].reserve(kBatch);
    };
    auto to = [&](size_t k, Event e) {
        open[k].push_back(std::move(e));
        if (open[k].size() >= kBatch) send(k);
    };
    try {
        ReadRun(
            db, detail.run.run_id, wanted,
            [&](const std::string& id, const an::GyroSample& s) {
                const auto& [k, name] = shard_of.at(id);
                to(k, GyroEvent{name, s});
            },
            [&](const motion::EncoderReading& e) {
                for (size_t k = 0; k < kShards; ++k) to(k, e);
            },
            [&](const an::AirSample& a) {
                for (size_t k = 0; k < kShards; ++k) to(k, a);
            },
            [&](const std::string& id, const an::PowerRecord& p) {
                const auto& [k, name] = shard_of.at(id);
                to(k, PowerEvent{name, p});
            });
        for (size_t k = 0; k < kShards; ++k) {
            if (!open[k].empty()) send(k);
            send(k);  // the empty batch: the end
        }
    } catch (...) {
        errors[kShards] = std::current_exception();
        for (BatchQueue& q : queues) q.Close();
    }
    for (std::thread& t : workers) t.join();
    for (size_t k = 0; k < kShards; ++k)  // a shard's own error first: it is why the reader stopped
        if (errors[k]) std::rethrow_exception(errors[k]);
    if (errors[kShards]) std::rethrow_exception(errors[kShards]);
    an::RunBinner b = std::move(shards[0]);
    for (size_t k = 1; k < kShards; ++k) b.Absorb(std::move(shards[k]));
    for (const st::PlateauRow& p : detail.plateaus)
        if (wanted.count(p.sensor_id) && b.unit(p.sensor_id))
            b.AddPlateau(p.sensor_id, PlateauOf(p));
    for (const st::SensitivityRow& s : detail.sensitivity_points)
        if (wanted.count(s.sensor_id) && b.unit(s.sensor_id))
            b.AddSensitivity(s.sensor_id, SensitivityOf(s));
    return b;
}

}  // namespace gyrocal::cli
