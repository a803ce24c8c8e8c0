#include "store/format/samples_csv.hpp"

#include <map>
#include <type_traits>
#include <variant>

#include "producers/csv/csv_writer.hpp"
#include "producers/csv/row_messages.hpp"
#include "store/db/replay_reader.hpp"
#include "store/recorder/message_fields.hpp"

namespace gyrocal::format {

int64_t WriteRunSamplesCsv(db::Db& db, const std::string& run_id, const std::string& sensor_id,
                           std::ostream& out) {
    db::ReplayReader reader(db, run_id);
    csv::LatestAt encoder_deg, chamber_c;
    std::map<std::string, int64_t> power_on;
    int64_t rows = 0;
    out << csv::kRecordHeader << '\n';
    while (auto row = reader.Next()) {
        std::visit(
            [&](const auto& r) {
                using T = std::decay_t<decltype(r)>;
                if constexpr (std::is_same_v<T, db::EncoderRow>) {
                    encoder_deg.Add(r.utime, r.angle_deg);
                } else if constexpr (std::is_same_v<T, db::ChamberStateRow>) {
                    chamber_c.Add(r.utime, r.air_c);
                } else if constexpr (std::is_same_v<T, db::PowerStateRow>) {
                    power_on[r.sensor_id] = r.power_on_utime;
                } else if constexpr (std::is_same_v<T, db::GyroRow>) {
                    if (!sensor_id.empty() && r.sensor_id != sensor_id) return;
                    gyro_sample_t s;
                    recorder::CopyFields(s, r);
                    const auto p = power_on.find(r.sensor_id);
                    out << csv::FormatRecordRow(
                               s, csv::kDefaultStartUtime, encoder_deg.At(r.utime),
                               chamber_c.At(r.utime),
                               p == power_on.end() ? std::nullopt : std::optional(p->second))
                        << '\n';
                    ++rows;
                }
            },
            *row);
    }
    return rows;
}

}  // namespace gyrocal::format
