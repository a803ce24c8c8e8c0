#include "producers/csv_source/csv_source_node.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::csv_source {

namespace {

// The temperature transfer of the options, validated by main.
sensor::TempTransfer TransferOf(const csv::ConversionOptions& conversion) {
    std::string err;
    return *conversion.Transfer(&err);
}

// The first pass: every row checked, none kept; nullopt (with the exit code in `exit_code`)
// when the file cannot be used.
std::optional<CsvCheck> CheckWholeFile(const CsvSourceOptions& o, int* exit_code) {
    std::ifstream in(o.file);
    if (!in) {
        process::PrintError(kCsvSourceProcess, "--file '" + o.file +
                                                   "' cannot be opened: " + std::strerror(errno) +
                                                   "; give a readable CSV file");
        *exit_code = 2;
        return std::nullopt;
    }
    try {
        csv::CsvReader reader(in, o.file, TransferOf(o.conversion), o.on_error, o.check_rows);
        CsvCheck c;
        while (reader.Next()) ++c.rows;
        c.unknown = reader.unknown();
        c.errors = reader.errors();
        c.skipped = reader.skipped();
        return c;
    } catch (const csv::CsvError& e) {
        process::PrintError(kCsvSourceProcess, e.what());
        std::cerr << kCsvSourceProcess
                  << ": nothing published (--on-error stop; use --on-error skip to drop bad "
                     "rows)\n";
        *exit_code = 1;
        return std::nullopt;
    }
}

// Unknown columns once, and the first skipped rows (--on-error skip) with a count of the rest.
void ReportReadProblems(const CsvSourceOptions& o, const CsvCheck& file) {
    if (!file.unknown.empty()) {
        std::string names;
        for (const auto& n : file.unknown) names += (names.empty() ? "" : ", ") + n;
        std::cerr << "gyrocal-csv-source: warning: " << o.file << ": ignoring unknown column(s) "
                  << names << "\n";
    }
    constexpr size_t kShown = 10;
    for (size_t i = 0; i < file.errors.size() && i < kShown; ++i) {
        std::cerr << "gyrocal-csv-source: skipped: " << file.errors[i] << "\n";
    }
    if (file.skipped > static_cast<long>(kShown)) {
        std::cerr << "gyrocal-csv-source: ... and " << file.skipped - static_cast<long>(kShown)
                  << " more bad rows skipped\n";
    }
}

}  // namespace

int ReplayCsvFile(const CsvSourceOptions& o) {
    int exit_code = 0;
    std::optional<CsvCheck> check = CheckWholeFile(o, &exit_code);
    if (!check) return exit_code;
    ReportReadProblems(o, *check);
    if (check->rows == 0) {  // nothing to replay is a bad file, not an empty run
        process::PrintError(
            kCsvSourceProcess,
            o.file + ": no data rows: " +
                (check->skipped > 0 ? "every one of the " + std::to_string(check->skipped) +
                                          " rows was bad (--on-error skip); fix them"
                                    : std::string("the header names the columns but no "
                                                  "row follows; give at least one row "
                                                  "of samples")));
        return 1;
    }
    if (o.check_rows >= 0) {
        std::cerr << kCsvSourceProcess << ": " << o.file << ": the header and the first "
                  << check->rows + check->skipped << " rows are valid (--check-rows "
                  << o.check_rows << "; nothing published)\n";
        return 0;
    }
    process::InstallStopHandlers();
    try {
        CsvSourceNode node(o, std::move(*check));
        return node.Run();
    } catch (const std::exception& e) {
        process::PrintError(kCsvSourceProcess, e.what());
        return 1;
    }
}

std::string CsvSourceOptions::Validate() const {
    if (!max && !(speed > 0.0 && speed <= 1e6)) {
        return "--speed " + text::Sig(speed) +
               " is out of range; valid: > 0 and <= 1e6 data seconds per wall second (or --max)";
    }
    if (!(max_rate_hz >= 1.0 && max_rate_hz <= 1e7)) {
        return "--max-rate-hz " + text::Sig(max_rate_hz) +
               " is out of range; valid: 1 to 1e7 messages per second";
    }
    if (!(drain_s >= 0.0 && drain_s <= 60.0)) {
        return "--drain-s " + text::Sig(drain_s) + " is out of range; valid: 0 to 60 s";
    }
    if (std::string e = flow.Validate(); !e.empty()) return e;
    return conversion.Validate();
}

CsvSourceNode::CsvSourceNode(const CsvSourceOptions& options, CsvCheck check)
    : options_(options),
      check_(std::move(check)),
      in_(options.file),
      reader_(in_, options.file, TransferOf(options.conversion), options.on_error),
      bus_(bus::BusOptions{options.lcm_url}),
      status_(bus_, "gyrocal-csv-source"),
      builder_(static_cast<int32_t>(options.conversion.encoder_counts_per_rev)),
      batcher_(bus_, options.flow.batch_samples) {
    if (options_.max)
        flow_ =
            std::make_unique<flow::FlowSource>(bus_, "gyrocal-csv-source", options_.flow.Window());
    // The file was checked whole a moment ago; one that changed since is an error, not data.
    if (!in_) throw std::runtime_error("--file '" + options.file + "' cannot be read again");
    next_row_ = reader_.Next();
    if (next_row_) first_time_s_ = next_row_->time_s;
    status_.SetExtra("rows_total", static_cast<double>(check_.rows));
    status_.SetExtra("rows_skipped_bad", static_cast<double>(check_.skipped));
}

csv::CsvRow CsvSourceNode::TakeRow() {
    csv::CsvRow row = std::move(*next_row_);
    next_row_ = reader_.Next();
    ++next_;
    return row;
}

double CsvSourceNode::DueSeconds() const {
    // [wall s after start] by data time since the first row (--speed only).
    return (next_row_->time_s - first_time_s_) / options_.speed;
}

void CsvSourceNode::PublishRow(const csv::CsvRow& row) {
    const int64_t utime = csv::StreamUtime(options_.conversion.start_utime, row.time_s);
    const csv::RowMessages m = builder_.Build(row, utime);
    // Encoder and chamber first: a recorder then already knows the table angle and air
    // temperature in force when the gyro sample of the same time arrives. Unbatched messages go
    // out after what the batcher holds, so no channel overtakes another.
    if (m.encoder) batcher_.AddEncoder(std::string(channels::kEncoder), *m.encoder);
    if (m.chamber || m.power) batcher_.Flush();
    if (m.chamber) bus_.Publish(std::string(channels::kChamberState), *m.chamber);
    if (m.power) bus_.Publish(channels::Power(m.power->sensor_id), *m.power);
    batcher_.Add(channels::Gyro(row.sensor_id), m.gyro);
    if (batcher_.full()) batcher_.Flush();
    last_utime_ = utime;
    messages_ += 1 + (m.encoder ? 1 : 0) + (m.chamber ? 1 : 0) + (m.power ? 1 : 0);
}

void CsvSourceNode::PaceByData(double elapsed_s, double* wait_s) {
    while (More() && DueSeconds() <= elapsed_s) PublishRow(TakeRow());
    batcher_.Flush();
    if (More()) *wait_s = std::clamp(DueSeconds() - elapsed_s, 0.0, 0.02);
}

void CsvSourceNode::PaceByRateCap(Clock::time_point now, double* wait_s) {
    // Token bucket at --max-rate-hz holding at most 4 ms of messages: publish what it allows (a
    // batch of about 2 ms), then sleep 2 ms so that receivers on this host get the cores. A
    // late turn never turns into a burst bigger than the cap. Small batches matter: lcm-logger
    // 1.3.1 queues only 30 messages per subscription.
    const double dt_s = std::chrono::duration<double>(now - last_turn_).count();
    last_turn_ = now;
    tokens_ = std::min(tokens_ + dt_s * options_.max_rate_hz,
                       std::max(1.0, 0.004 * options_.max_rate_hz));
    while (More() && tokens_ >= 1.0) {
        const int64_t before = messages_;
        PublishRow(TakeRow());
        tokens_ -= static_cast<double>(messages_ - before);
    }
    batcher_.Flush();
    *wait_s = 0.002;
}

void CsvSourceNode::PaceByConsumers(Clock::time_point now, double* wait_s) {
    // As much as the slowest consumer has room for (flow_window.hpp), for at most 20 ms of
    // publishing before the loop serves STATUS and signals again.
    flow_->Sync(last_utime_);
    std::optional<int64_t> credit = flow_->Credit();
    if (!credit) return PaceByRateCap(now, wait_s);  // nobody answers: the cap of old
    last_turn_ = now;
    if (*credit <= 0) {
        flow_->WaitForCredit(std::chrono::milliseconds(20));
        return;
    }
    const auto until = now + std::chrono::milliseconds(20);
    while (More() && credit && *credit > 0 && Clock::now() < until) {
        PublishRow(TakeRow());
        if (batcher_.held() > 0) continue;  // nothing went out yet
        flow_->Sync(last_utime_);
        credit = flow_->Credit();
    }
    batcher_.Flush();
    flow_->Sync(last_utime_);
    for (const std::string& line : flow_->TakeReports())
        std::cerr << "gyrocal-csv-source: flow: " << line << "\n";
}

bool CsvSourceNode::Step() {
    const auto now = Clock::now();
    if (!started_) {
        started_ = true;
        start_ = now;
        last_turn_ = now;
        status_.set_state("replaying");
        if (flow_) flow_->Discover();
    }
    if (More()) {
        const double elapsed_s = std::chrono::duration<double>(now - start_).count();
        double wait_s = 0.0;
        if (flow_) {
            PaceByConsumers(now, &wait_s);
        } else {
            PaceByData(elapsed_s, &wait_s);
        }
        status_.SetExtra("rows_published", static_cast<double>(next_));
        if (flow_)
            for (const auto& [name, value] : flow_->Extras()) status_.SetExtra(name, value);
        if (!More()) {
            finished_ = Clock::now();
            status_.set_state("draining");
            return false;
        }
        if (wait_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
        return false;
    }
    // Drain: every consumer answers the last mark (so it has every row), or, without flow
    // control, the receivers get --drain-s to empty their sockets before the final STATUS.
    if (flow_ && flow_->paced_consumers() > 0) {
        const bool all = flow_->Drain(last_utime_);
        for (const auto& [name, value] : flow_->Extras()) status_.SetExtra(name, value);
        for (const std::string& line : flow_->TakeReports())
            std::cerr << "gyrocal-csv-source: flow: " << line << "\n";
        if (!all) std::cerr << "gyrocal-csv-source: flow: not every consumer answered the end\n";
        return true;
    }
    if (Clock::now() - finished_ >= std::chrono::duration<double>(options_.drain_s)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return false;
}

int CsvSourceNode::Run() {
    if (!More()) finished_ = Clock::now();
    process::RunLoop(
        bus_, status_, [this] { return Step(); }, std::chrono::milliseconds(0));
    const bus::BusCounters& c = bus_.counters();
    std::cerr << "gyrocal-csv-source: published " << next_ << " of " << check_.rows << " rows ("
              << messages_ << " messages) from " << options_.file;
    if (check_.skipped > 0) std::cerr << "; skipped " << check_.skipped << " bad rows";
    if (process::StopRequested() && More()) std::cerr << "; stopped by signal";
    std::cerr << "\n";
    if (c.publish_errors > 0) {
        process::PrintError(
            kCsvSourceProcess,
            std::to_string(c.publish_errors) + " messages could not be sent (LCM publish failed)");
        return 1;
    }
    return 0;
}

}  // namespace gyrocal::csv_source
