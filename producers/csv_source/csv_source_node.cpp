#include "csv_source_node.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include "bus/channels.hpp"
#include "runtime/process_main.hpp"
#include "runtime/shutdown.hpp"
#include "text/number.hpp"

namespace gyrocal {
namespace {
// As a person typed it: "0", "-1.5", "1e+07" (std::to_string would print "0.000000").
}  // namespace

namespace {

// Reads the whole file; nullopt (with the exit code in `exit_code`) when it cannot be used.
std::optional<csv::CsvFile> ReadWholeFile(const CsvSourceOptions& o, int* exit_code) {
    std::ifstream in(o.file);
    if (!in) {
        PrintError(kCsvSourceProcess, "--file '" + o.file + "' cannot be opened: " +
                                              std::strerror(errno) + "; give a readable CSV file");
        *exit_code = 2;
        return std::nullopt;
    }
    std::string err;
    const sensor::TempTransfer transfer = *o.conversion.Transfer(&err);
    try {
        return csv::ReadCsv(in, o.file, transfer, o.on_error, o.check_rows);
    } catch (const csv::CsvError& e) {
        PrintError(kCsvSourceProcess, e.what());
        std::cerr << kCsvSourceProcess
                  << ": nothing published (--on-error stop; use --on-error skip to drop bad "
                     "rows)\n";
        *exit_code = 1;
        return std::nullopt;
    }
}

// Unknown columns once, and the first skipped rows (--on-error skip) with a count of the rest.
void ReportReadProblems(const CsvSourceOptions& o, const csv::CsvFile& file) {
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
    if (file.errors.size() > kShown) {
        std::cerr << "gyrocal-csv-source: ... and " << file.errors.size() - kShown
                  << " more bad rows skipped\n";
    }
}

}  // namespace

int ReplayCsvFile(const CsvSourceOptions& o) {
    int exit_code = 0;
    std::optional<csv::CsvFile> file = ReadWholeFile(o, &exit_code);
    if (!file) return exit_code;
    ReportReadProblems(o, *file);
    if (file->rows.empty()) {  // nothing to replay is a bad file, not an empty run
        PrintError(kCsvSourceProcess,
                   o.file + ": no data rows: " +
                       (file->skipped > 0 ? "every one of the " + std::to_string(file->skipped) +
                                                " rows was bad (--on-error skip); fix them"
                                          : std::string("the header names the columns but no "
                                                        "row follows; give at least one row "
                                                        "of samples")));
        return 1;
    }
    if (o.check_rows >= 0) {
        std::cerr << kCsvSourceProcess << ": " << o.file << ": the header and the first "
                  << file->rows.size() + file->skipped << " rows are valid (--check-rows "
                  << o.check_rows << "; nothing published)\n";
        return 0;
    }
    InstallStopHandlers();
    try {
        CsvSourceNode node(o, std::move(*file));
        return node.Run();
    } catch (const std::exception& e) {
        PrintError(kCsvSourceProcess, e.what());
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
    return conversion.Validate();
}

CsvSourceNode::CsvSourceNode(const CsvSourceOptions& options, csv::CsvFile file)
    : options_(options),
      file_(std::move(file)),
      bus_(BusOptions{options.lcm_url}),
      status_(bus_, "gyrocal-csv-source"),
      builder_(static_cast<int32_t>(options.conversion.encoder_counts_per_rev)) {
    status_.SetExtra("rows_total", static_cast<double>(file_.rows.size()));
    status_.SetExtra("rows_skipped_bad", static_cast<double>(file_.skipped));
}

double CsvSourceNode::DueSeconds(size_t i) const {
    // [wall s after start] by data time since the first row (--speed only).
    return (file_.rows[i].time_s - file_.rows.front().time_s) / options_.speed;
}

void CsvSourceNode::PublishRow(const csv::CsvRow& row) {
    const int64_t utime = csv::StreamUtime(options_.conversion.start_utime, row.time_s);
    const csv::RowMessages m = builder_.Build(row, utime);
    // Encoder and chamber first: a recorder then already knows the table angle and air
    // temperature in force when the gyro sample of the same time arrives.
    if (m.encoder) bus_.Publish(std::string(channels::kEncoder), *m.encoder);
    if (m.chamber) bus_.Publish(std::string(channels::kChamberState), *m.chamber);
    if (m.power) bus_.Publish(channels::Power(m.power->sensor_id), *m.power);
    bus_.Publish(channels::Gyro(row.sensor_id), m.gyro);
    messages_ += 1 + (m.encoder ? 1 : 0) + (m.chamber ? 1 : 0) + (m.power ? 1 : 0);
}

bool CsvSourceNode::Step() {
    const auto now = Clock::now();
    if (!started_) {
        started_ = true;
        start_ = now;
        last_turn_ = now;
        status_.set_state("replaying");
    }
    if (next_ < file_.rows.size()) {
        const double elapsed_s = std::chrono::duration<double>(now - start_).count();
        double wait_s = 0.0;
        if (options_.max) {
            // Token bucket at --max-rate-hz holding at most 4 ms of messages: publish what it
            // allows (a batch of about 2 ms), then sleep 2 ms so that receivers on this host get
            // the cores. A late turn never turns into a burst bigger than the cap. Small batches
            // matter: lcm-logger 1.3.1 queues only 30 messages per subscription.
            const double dt_s = std::chrono::duration<double>(now - last_turn_).count();
            last_turn_ = now;
            tokens_ = std::min(tokens_ + dt_s * options_.max_rate_hz,
                               std::max(1.0, 0.004 * options_.max_rate_hz));
            while (next_ < file_.rows.size() && tokens_ >= 1.0) {
                const int64_t before = messages_;
                PublishRow(file_.rows[next_++]);
                tokens_ -= static_cast<double>(messages_ - before);
            }
            wait_s = 0.002;
        } else {
            while (next_ < file_.rows.size() && DueSeconds(next_) <= elapsed_s) {
                PublishRow(file_.rows[next_++]);
            }
            if (next_ < file_.rows.size()) {
                wait_s = std::clamp(DueSeconds(next_) - elapsed_s, 0.0, 0.02);
            }
        }
        status_.SetExtra("rows_published", static_cast<double>(next_));
        if (next_ == file_.rows.size()) {
            finished_ = Clock::now();
            status_.set_state("draining");
            return false;
        }
        if (wait_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
        return false;
    }
    // Drain: let receivers empty their sockets before the final STATUS and exit.
    if (Clock::now() - finished_ >= std::chrono::duration<double>(options_.drain_s)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return false;
}

int CsvSourceNode::Run() {
    if (file_.rows.empty()) finished_ = Clock::now();
    RunLoop(
        bus_, status_, [this] { return Step(); }, std::chrono::milliseconds(0));
    const BusCounters& c = bus_.counters();
    std::cerr << "gyrocal-csv-source: published " << next_ << " of " << file_.rows.size()
              << " rows (" << messages_ << " messages) from " << options_.file;
    if (file_.skipped > 0) std::cerr << "; skipped " << file_.skipped << " bad rows";
    if (StopRequested() && next_ < file_.rows.size()) std::cerr << "; stopped by signal";
    std::cerr << "\n";
    if (c.publish_errors > 0) {
        PrintError(kCsvSourceProcess, std::to_string(c.publish_errors) +
                                          " messages could not be sent (LCM publish failed)");
        return 1;
    }
    return 0;
}

}  // namespace gyrocal
