#pragma once
// The CSV replay process: a file checked whole in a first pass (csv/csv_file.hpp; nothing is
// kept but counts and the first messages, so a day of data fits in bounded memory) is read again
// and published row by row in file order, paced by data time (--speed) or as fast as every consumer
// keeps up (--max: flow control, lcmtypes/flow; with no consumer answering, a message-rate cap).
//
// Threads: one. Run() is RunLoop with a zero poll; each loop turn publishes the rows that are
// due (or that the consumers have room for), then sleeps until the next is due or waits for
// the consumers' answers (at most 20 ms, so STATUS and SIGINT stay responsive). It stops after
// the last row once every consumer has answered the last mark (--max), or after a short drain.
#include <chrono>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/bus/sample_batcher.hpp"
#include "lcmtypes/flow/flow_source.hpp"
#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/status.hpp"
#include "producers/csv/conversion_options.hpp"
#include "producers/csv/csv_file.hpp"
#include "producers/csv/row_messages.hpp"

namespace gyrocal::csv_source {

// --max's default rate: well below what our receivers (bus layer, unbounded queues) kept up with,
// so that a pipeline of several processes has room; lcm-logger 1.3.1 (30-message subscription
// queue) loses sooner. The measured losses per rate: producers/csv_source/README.md.
inline constexpr double kDefaultMaxRateHz = 20000.0;
inline constexpr const char* kCsvSourceProcess = "gyrocal-csv-source";

struct CsvSourceOptions {
    std::string file;
    std::string lcm_url;
    double speed = 1.0;                      // [data s / wall s]
    bool max = false;                        // pace by max_rate_hz instead of data time
    double max_rate_hz = kDefaultMaxRateHz;  // [msg/s] cap of --max when no consumer answers
    process::SourceFlowOptions flow = process::SourceFlowOptions::Defaults();
    csv::OnError on_error = csv::OnError::kStop;
    double drain_s = 0.5;  // [s] wait after the last row before exiting
    long check_rows = -1;  // >= 0: check the header and this many rows, publish nothing
    csv::ConversionOptions conversion = csv::ConversionOptions::Defaults();
    static CsvSourceOptions Defaults() { return {}; }
    std::string Validate() const;  // "" or one line naming the option and the valid range
};

// What the first pass over a file found: how many rows are valid, the columns it ignores, the
// rows it skips (the first messages and the count).
struct CsvCheck {
    long rows = 0;
    std::vector<std::string> unknown;
    std::vector<std::string> errors;
    long skipped = 0;
};

// The whole gyrocal-csv-source after option parsing: reads and checks the whole file (bad rows
// per o.on_error, reported on stderr as FILE:LINE), then publishes it with a CsvSourceNode.
// Returns the exit code: 2 when the file cannot be opened, 1 for a malformed file under
// OnError::kStop (nothing published) or a publish failure, 0 when done or stopped.
// With o.check_rows >= 0 it only reads the header and that many rows (the check `gyrocal
// calibrate` makes before it starts a run) and publishes nothing: 0 valid, 1 malformed.
int ReplayCsvFile(const CsvSourceOptions& o);

class CsvSourceNode {
public:
    // Opens options.file again for the second pass; `check` is the first pass's.
    CsvSourceNode(const CsvSourceOptions& options, CsvCheck check);
    // Returns the exit code: 0 done or stopped, 1 when publishing failed.
    int Run();
    // The node's bus: tests subscribe to it over memq://.
    bus::Bus& bus() { return bus_; }

private:
    using Clock = std::chrono::steady_clock;
    bool Step();  // true when finished
    bool More() const { return next_row_.has_value(); }
    csv::CsvRow TakeRow();  // the next row (More() first); reads the one after it
    void PaceByData(double elapsed_s, double* wait_s);
    void PaceByConsumers(Clock::time_point now, double* wait_s);
    void PaceByRateCap(Clock::time_point now, double* wait_s);
    void PublishRow(const csv::CsvRow& row);
    double DueSeconds() const;  // [wall s after start] when the next row is due (--speed)

    CsvSourceOptions options_;
    CsvCheck check_;
    std::ifstream in_;
    csv::CsvReader reader_;
    std::optional<csv::CsvRow> next_row_;
    double first_time_s_ = 0;
    bus::Bus bus_;
    process::StatusReporter status_;
    csv::MessageBuilder builder_;
    bus::SampleBatcher batcher_;
    std::unique_ptr<flow::FlowSource> flow_;  // --max only
    int64_t last_utime_ = 0;                  // [us] data time of the newest row published
    size_t next_ = 0;
    int64_t messages_ = 0;
    bool started_ = false;
    Clock::time_point start_{};
    Clock::time_point finished_{};
    Clock::time_point last_turn_{};  // --max: previous loop turn
    double tokens_ = 1.0;            // --max: messages that may go out now
};

}  // namespace gyrocal::csv_source
