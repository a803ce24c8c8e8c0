#include "run_loader.hpp"

#include <set>
#include <type_traits>
#include <variant>

#include "replay_reader.hpp"

namespace gyrocal::cli {

namespace an = gyrocal::analysis;
namespace st = gyrocal::store;

std::map<std::string, an::SensorRun> LoadSensorRuns(st::Db& db, const st::RunDetail& detail,
                                                    const std::vector<std::string>& sensors) {
    const std::set<std::string> wanted(sensors.begin(), sensors.end());
    std::map<std::string, std::vector<an::GyroSample>> gyro;
    std::map<std::string, std::vector<an::PowerRecord>> power;
    std::vector<motion::EncoderReading> encoder;
    std::vector<an::AirSample> air;  // one chamber per run: every unit sat in the same air
    st::ReplayReader reader(db, detail.run.run_id);
    while (auto row = reader.Next()) {
        std::visit(
            [&](const auto& r) {
                using T = std::decay_t<decltype(r)>;
                if constexpr (std::is_same_v<T, st::GyroRow>) {
                    if (wanted.count(r.sensor_id))
                        gyro[r.sensor_id].push_back(
                            {r.utime, r.seq, r.temp_c, r.gyro_v, r.supply_v});
                } else if constexpr (std::is_same_v<T, st::EncoderRow>) {
                    encoder.push_back({r.utime, r.counts, r.counts_per_rev});
                } else if constexpr (std::is_same_v<T, st::ChamberStateRow>) {
                    air.push_back({r.utime, r.air_c});
                } else if constexpr (std::is_same_v<T, st::PowerStateRow>) {
                    power[r.sensor_id].push_back({r.utime, r.power_on_utime, r.source});
                }
            },
            *row);
    }
    std::map<std::string, an::SensorRun> runs;
    for (const std::string& id : sensors) {
        std::vector<an::PlateauInput> plateaus;
        for (const st::PlateauRow& p : detail.plateaus)
            if (p.sensor_id == id)
                plateaus.push_back({p.plateau_id, p.start_utime, p.end_utime, p.temp_mean_c,
                                    p.temp_sem_c, p.gyro_mean_v, p.gyro_sem_v, p.n_samples});
        std::vector<an::SensitivityInput> sens;
        for (const st::SensitivityRow& s : detail.sensitivity_points)
            if (s.sensor_id == id)
                sens.push_back({s.rotation_id, s.utime, s.temp_c, s.direction,
                                s.sensitivity_v_per_dps, s.sensitivity_stderr_v_per_dps,
                                s.accepted});
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
    st::ReplayReader reader(db, detail.run.run_id);
    while (auto row = reader.Next()) {
        std::visit(
            [&](const auto& r) {
                using T = std::decay_t<decltype(r)>;
                if constexpr (std::is_same_v<T, st::GyroRow>) {
                    if (wanted.count(r.sensor_id))
                        b.AddGyro(r.sensor_id, {r.utime, r.seq, r.temp_c, r.gyro_v, r.supply_v});
                } else if constexpr (std::is_same_v<T, st::EncoderRow>) {
                    b.AddEncoder({r.utime, r.counts, r.counts_per_rev});
                } else if constexpr (std::is_same_v<T, st::ChamberStateRow>) {
                    b.AddAir({r.utime, r.air_c});
                } else if constexpr (std::is_same_v<T, st::PowerStateRow>) {
                    if (wanted.count(r.sensor_id))
                        b.AddPower(r.sensor_id, {r.utime, r.power_on_utime, r.source});
                }
            },
            *row);
    }
    b.Flush();
    for (const st::PlateauRow& p : detail.plateaus)
        if (wanted.count(p.sensor_id) && b.unit(p.sensor_id))
            b.AddPlateau(p.sensor_id, {p.plateau_id, p.start_utime, p.end_utime, p.temp_mean_c,
                                       p.temp_sem_c, p.gyro_mean_v, p.gyro_sem_v, p.n_samples});
    for (const st::SensitivityRow& s : detail.sensitivity_points)
        if (wanted.count(s.sensor_id) && b.unit(s.sensor_id))
            b.AddSensitivity(s.sensor_id,
                             {s.rotation_id, s.utime, s.temp_c, s.direction,
                              s.sensitivity_v_per_dps, s.sensitivity_stderr_v_per_dps, s.accepted});
    return b;
}

}  // namespace gyrocal::cli
