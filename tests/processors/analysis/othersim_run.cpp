#include "tests/processors/analysis/othersim_run.hpp"

#include <cmath>
#include <sstream>

#include "producers/csv/csv_file.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/support/othersim/generator.hpp"

namespace gyrocal::analysis::testing {

OthersimRun MakeOthersimRun(othersim::Options o) {
    o.units = 1;
    std::ostringstream text;
    const othersim::Generated g = othersim::Generate(o, text);
    std::istringstream in(text.str());
    const csv::CsvFile f =
        csv::ReadCsv(in, "othersim.csv", sensor::TempTransfer{}, csv::OnError::kStop);
    const othersim::UnitTruth& u = g.units.at(0);
    OthersimRun out;
    std::vector<GyroSample> gyro;
    std::vector<motion::EncoderReading> enc;
    std::vector<AirSample> air;  // its chamber_c column, as the importer would publish it
    const int32_t cpr = 20000;   // the CSV importer's default
    int64_t seq = 0;
    const int64_t first_us = f.rows.empty() ? 0 : csv::TimeUs(f.rows.front().time_s);
    for (const csv::CsvRow& r : f.rows) {
        const int64_t utime = csv::TimeUs(r.time_s);
        gyro.push_back({.utime = utime,
                        .seq = seq++,
                        .gyro_v = r.gyro_v,
                        .temp_c = r.temp_c,
                        .supply_v = r.supply_v ? *r.supply_v : kNan});
        enc.push_back({utime, std::llround(*r.encoder_deg * cpr / 360.0), cpr});
        if (r.chamber_c) air.push_back({utime, *r.chamber_c});
        const double t_s = (utime - first_us) * 1e-6;
        out.truth_offset_v.push_back(u.OffsetV(u.DieFromMeasuredC(r.temp_c)) +
                                     o.effects.warmup_v * std::exp(-t_s / o.effects.warmup_tau_s) +
                                     o.effects.OutsideV(t_s));
    }
    out.run = BuildSensorRun(u.sensor_id, std::move(gyro), enc, {}, {});
    AddChamberAir(out.run, std::move(air));
    return out;
}

}  // namespace gyrocal::analysis::testing
