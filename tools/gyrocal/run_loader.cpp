#include "tools/gyrocal/run_loader.hpp"

#include <set>
#include <type_traits>
#include <variant>

#include "store/db/replay_reader.hpp"

namespace gyrocal::cli {

namespace an = gyrocal::analysis;
namespace st = gyrocal::store;

namespace {

// The run's recorded rows in their order, each handed on as the analysis reads it: gyro samples
// and power records of the `wanted` sensors (the others are passed over), every encoder reading
// and chamber air reading.
template <class OnGyro, class OnEncoder, class OnAir, class OnPower>
void ReadRun(st::Db& db, const std::string& run_id, const std::set<std::string>& wanted,
             OnGyro on_gyro, OnEncoder on_encoder, OnAir on_air, OnPower on_power) {
    st::ReplayReader reader(db, run_id);
    while (auto row = reader.Next()) {
        std::visit(
            [&](const auto& r) {
                using T = std::decay_t<decltype(r)>;
                if constexpr (std::is_same_v<T, st::GyroRow>) {
                    if (wanted.count(r.sensor_id))
                        on_gyro(r.sensor_id,
                                an::GyroSample{r.utime, r.seq, r.temp_c, r.gyro_v, r.supply_v});
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

analysis::RunBinner LoadBinnedRun(store::Db& db, const st::RunDetail& detail,
                                  const std::vector<std::string>& sensors,
                                  const analysis::IncrementalOptions& options) {
    const std::set<std::string> wanted(sensors.begin(), sensors.end());
    an::RunBinner b(options);
    ReadRun(
        db, detail.run.run_id, wanted,
        [&](const std::string& id, const an::GyroSample& s) { b.AddGyro(id, s); },
        [&](const motion::EncoderReading& e) { b.AddEncoder(e); },
        [&](const an::AirSample& a) { b.AddAir(a); },
        [&](const std::string& id, const an::PowerRecord& p) { b.AddPower(id, p); });
    b.Flush();
    for (const st::PlateauRow& p : detail.plateaus)
        if (wanted.count(p.sensor_id) && b.unit(p.sensor_id))
            b.AddPlateau(p.sensor_id, PlateauOf(p));
    for (const st::SensitivityRow& s : detail.sensitivity_points)
        if (wanted.count(s.sensor_id) && b.unit(s.sensor_id))
            b.AddSensitivity(s.sensor_id, SensitivityOf(s));
    return b;
}

}  // namespace gyrocal::cli
