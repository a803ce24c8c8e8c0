#include "producers/line_source/line_source_node.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <thread>
#include <vector>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::line_source {
namespace {
sensor::TempTransfer TransferOf(const csv::ConversionOptions& conversion) {
    std::string err;
    return *conversion.Transfer(&err);  // validated by main
}
}  // namespace

std::string LineSourceOptions::Validate() const {
    if (!(drain_s >= 0.0 && drain_s <= 60.0)) {
        return "--drain-s " + text::Sig(drain_s) + " is out of range; valid: 0 to 60 s";
    }
    if (std::string e = flow_options.Validate(); !e.empty()) return e;
    if (flow && time == TimeSource::kWall)
        return "--flow holds the input back, which --time wall (a live stream) must not be; "
               "use --time stream with --flow";
    return conversion.Validate();
}

LineSourceNode::LineSourceNode(const LineSourceOptions& options, std::unique_ptr<LineInput> input)
    : options_(options),
      input_(std::move(input)),
      bus_(bus::BusOptions{options.lcm_url}),
      status_(bus_, "gyrocal-line-source"),
      stream_(input_->name(), TransferOf(options.conversion)),
      builder_(static_cast<int32_t>(options.conversion.encoder_counts_per_rev)),
      batcher_(bus_, options.flow_options.batch_samples) {
    if (options_.flow)
        flow_ = std::make_unique<flow::FlowSource>(bus_, "gyrocal-line-source",
                                                   options_.flow_options.Window());
    status_.set_state("waiting_header");
}

int64_t LineSourceNode::Utime(const csv::CsvRow& row) {
    if (options_.time == TimeSource::kStream) {
        return csv::StreamUtime(options_.conversion.start_utime, row.time_s);
    }
    // Wall time at reception; kept strictly increasing so that two lines read in the same
    // microsecond still give every sensor increasing utimes.
    const int64_t now = bus::WallClockUtime();
    last_wall_utime_ = std::max(now, last_wall_utime_ + 1);
    return last_wall_utime_;
}

void LineSourceNode::HandleLine(const InputLine& line) {
    const LineOutcome o = stream_.Feed(line);
    switch (o.kind) {
        case LineOutcome::Kind::kIgnored:
            return;
        case LineOutcome::Kind::kFatal:
            fatal_ = o.message;
            return;
        case LineOutcome::Kind::kBad:
            ++bad_lines_;
            status_.Reject("bad_line", o.message);
            return;
        case LineOutcome::Kind::kHeader:
            if (!o.unknown_columns.empty()) {
                std::string names;
                for (const auto& n : o.unknown_columns) names += (names.empty() ? "" : ", ") + n;
                std::cerr << "gyrocal-line-source: warning: " << input_->name()
                          << ": ignoring unknown column(s) " << names << "\n";
            }
            status_.set_state("streaming");
            return;
        case LineOutcome::Kind::kRow:
            break;
    }
    const csv::CsvRow& row = *o.row;
    last_utime_ = Utime(row);
    const csv::RowMessages m = builder_.Build(row, last_utime_);
    if (m.encoder) batcher_.AddEncoder(std::string(channels::kEncoder), *m.encoder);
    if (m.chamber || m.power) batcher_.Flush();  // no channel overtakes another
    if (m.chamber) bus_.Publish(std::string(channels::kChamberState), *m.chamber);
    if (m.power) bus_.Publish(channels::Power(m.power->sensor_id), *m.power);
    batcher_.Add(channels::Gyro(row.sensor_id), m.gyro);
    if (batcher_.full()) batcher_.Flush();
    ++published_rows_;
}

bool LineSourceNode::Step() {
    if (!fatal_.empty()) return true;
    if (eof_) return true;
    if (flow_) {
        if (!flow_->discovered()) flow_->Discover();
        flow_->Sync(last_utime_);
        const std::optional<int64_t> credit = flow_->Credit();
        if (credit && *credit <= 0) {
            flow_->WaitForCredit(std::chrono::milliseconds(20));  // the pipe holds the writer
            return false;
        }
    }
    std::vector<InputLine> lines;
    const bool more = input_->Read(50, &lines);
    for (const InputLine& l : lines) {
        HandleLine(l);
        if (!fatal_.empty()) return true;
    }
    batcher_.Flush();
    status_.SetExtra("rows_published", static_cast<double>(published_rows_));
    status_.SetExtra("lines_bad", static_cast<double>(bad_lines_));
    if (flow_) {
        flow_->Sync(last_utime_);
        for (const auto& [name, value] : flow_->Extras()) status_.SetExtra(name, value);
        for (const std::string& line : flow_->TakeReports())
            std::cerr << "gyrocal-line-source: flow: " << line << "\n";
    }
    if (!more) return AtEnd();
    return false;
}

bool LineSourceNode::AtEnd() {
    eof_ = true;
    status_.set_state("draining");
    if (flow_ && flow_->paced_consumers() > 0) {
        if (!flow_->Drain(last_utime_))
            std::cerr << "gyrocal-line-source: flow: not every consumer answered the end\n";
        return true;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.drain_s));
    return true;
}

int LineSourceNode::Run() {
    try {
        process::RunLoop(
            bus_, status_, [this] { return Step(); }, std::chrono::milliseconds(0));
    } catch (const std::runtime_error& e) {
        std::cerr << "gyrocal-line-source: error: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "gyrocal-line-source: published " << published_rows_ << " rows from "
              << input_->name() << "; skipped " << bad_lines_ << " bad lines\n";
    if (!fatal_.empty()) {
        std::cerr << "gyrocal-line-source: error: " << fatal_ << "\n";
        return 1;
    }
    if (bus_.counters().publish_errors > 0) {
        std::cerr << "gyrocal-line-source: error: " << bus_.counters().publish_errors
                  << " messages could not be sent (LCM publish failed)\n";
        return 1;
    }
    return 0;
}

}  // namespace gyrocal::line_source
