#include "producers/csv_record/csv_record_node.hpp"

#include <cmath>
#include <iostream>
#include <stdexcept>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::csv_record {

std::string CsvRecordOptions::Validate() const {
    if (out.empty()) return "--out is required: the CSV file to write";
    for (const std::string& id : sensors) {
        if (!channels::IsValidSensorId(id)) {
            return "--sensors: '" + id + "' is not a valid sensor id; use 1-32 letters, digits, " +
                   "'-' or '_', comma separated";
        }
    }
    if (!(idle_exit_s >= 0.0 && idle_exit_s <= 86400.0)) {
        return "--idle-exit-s " + text::Sig(idle_exit_s) +
               " is out of range; valid: 0 (never) to 86400 s";
    }
    return "";
}

CsvRecordNode::CsvRecordNode(const CsvRecordOptions& options)
    : options_(options),
      out_(options.out, std::ios::out | std::ios::trunc),
      bus_(bus::BusOptions{options.lcm_url}),
      status_(bus_, "gyrocal-csv-record") {
    if (!out_) throw std::runtime_error("--out '" + options.out + "' cannot be created");
    out_ << csv::kRecordHeader << '\n';

    auto on_gyro = [this](const gyro_sample_t& s, const std::string& channel) {
        const auto id = channels::SensorOf(channels::kGyroPrefix, channel);
        if (!id || *id != s.sensor_id) {
            status_.Reject("sensor_mismatch", "sample of '" + s.sensor_id + "' on " + channel);
            return;
        }
        // Every written row must read back through gyrocal-csv-source: required values finite,
        // time strictly increasing per sensor.
        if (!std::isfinite(s.gyro_v) || !std::isfinite(s.temp_v)) {
            status_.Reject("nonfinite_sample", channel + " seq " + std::to_string(s.seq) +
                                                   ": gyro_v or temp_v is not finite; not written");
            return;
        }
        auto [last, first] = last_utime_.try_emplace(s.sensor_id, s.utime);
        if (!first && s.utime <= last->second) {
            status_.Reject("out_of_order", channel + " seq " + std::to_string(s.seq) + ": utime " +
                                               std::to_string(s.utime) + " not after " +
                                               std::to_string(last->second) + "; not written");
            return;
        }
        last->second = s.utime;
        out_ << csv::FormatRecordRow(s, options_.time_origin_utime, encoder_deg_.At(s.utime),
                                     chamber_c_.At(s.utime), PowerOn(s.sensor_id))
             << '\n';
        ++rows_;
    };
    if (options_.sensors.empty()) {
        bus_.Subscribe<gyro_sample_t>(channels::AllSensors(channels::kGyroPrefix), on_gyro);
    } else {
        for (const std::string& id : options_.sensors) {
            bus_.Subscribe<gyro_sample_t>(channels::Gyro(id), on_gyro);
        }
    }
    bus_.Subscribe<encoder_sample_t>(std::string(channels::kEncoder),
                                     [this](const encoder_sample_t& e, const std::string&) {
                                         KeepFinite(encoder_deg_, e.utime, e.angle_deg,
                                                    "nonfinite_encoder", "ENCODER angle_deg");
                                     });
    bus_.Subscribe<chamber_state_t>(
        std::string(channels::kChamberState), [this](const chamber_state_t& c, const std::string&) {
            KeepFinite(chamber_c_, c.utime, c.air_c, "nonfinite_chamber", "CHAMBER_STATE air_c");
        });
    bus_.Subscribe<power_state_t>(channels::AllSensors(channels::kPowerPrefix),
                                  [this](const power_state_t& p, const std::string&) {
                                      power_on_utime_[p.sensor_id] = p.power_on_utime;
                                  });
}

void CsvRecordNode::KeepFinite(csv::LatestAt& series, int64_t utime, double value,
                               const std::string& reject_key, const std::string& field) {
    if (!std::isfinite(value)) {
        status_.Reject(reject_key, field + " is not finite");
        return;
    }
    series.Add(utime, value);
}

std::optional<int64_t> CsvRecordNode::PowerOn(const std::string& sensor_id) const {
    const auto it = power_on_utime_.find(sensor_id);
    if (it == power_on_utime_.end()) return std::nullopt;
    return it->second;
}

bool CsvRecordNode::Idle() {
    const auto now = Clock::now();
    if (now - last_flush_ >= std::chrono::seconds(1)) {
        out_.flush();
        last_flush_ = now;
        status_.SetExtra("rows_written", static_cast<double>(rows_));
    }
    if (bus_.counters().received != last_received_) {
        last_received_ = bus_.counters().received;
        last_activity_ = now;
    }
    return options_.idle_exit_s > 0 &&
           now - last_activity_ >= std::chrono::duration<double>(options_.idle_exit_s);
}

void CsvRecordNode::PublishStatus() {
    status_.SetExtra("rows_written", static_cast<double>(rows_));
    status_.PublishNow();
}

int CsvRecordNode::Run() {
    process::RunLoop(
        bus_, status_, [this] { return Idle(); }, std::chrono::milliseconds(20));
    return Finish();
}

int CsvRecordNode::Finish() {
    out_.flush();
    out_.close();
    std::cerr << "gyrocal-csv-record: wrote " << rows_ << " rows to " << options_.out << "\n";
    if (!out_) {
        std::cerr << "gyrocal-csv-record: error: writing '" << options_.out << "' failed\n";
        return 1;
    }
    return 0;
}

}  // namespace gyrocal::csv_record
