#pragma once
// The CSV replay process: rows already read and validated (csv/csv_file.hpp) are published in
// file order, paced by data time (--speed) or by a message-rate cap (--max).
//
// Threads: one. Run() is RunLoop with a zero poll; each loop turn publishes the rows that are
// due, then sleeps until the next is due (at most 20 ms, so STATUS and SIGINT stay responsive).
// It stops after the last row plus a short drain, or on SIGINT/SIGTERM.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "bus/bus.hpp"
#include "runtime/status.hpp"
#include "csv/conversion_options.hpp"
#include "csv/csv_file.hpp"
#include "csv/row_messages.hpp"

namespace gyrocal {

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
    double max_rate_hz = kDefaultMaxRateHz;  // [msg/s] cap of --max
    csv::OnError on_error = csv::OnError::kStop;
    double drain_s = 0.5;  // [s] wait after the last row before exiting
    long check_rows = -1;  // >= 0: check the header and this many rows, publish nothing
    csv::ConversionOptions conversion = csv::ConversionOptions::Defaults();
    static CsvSourceOptions Defaults() { return {}; }
    std::string Validate() const;  // "" or one line naming the option and the valid range
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
    CsvSourceNode(const CsvSourceOptions& options, csv::CsvFile file);
    // Returns the exit code: 0 done or stopped, 1 when publishing failed.
    int Run();
    // The node's bus: tests subscribe to it over memq://.
    Bus& bus() { return bus_; }

private:
    using Clock = std::chrono::steady_clock;
    bool Step();  // true when finished
    void PublishRow(const csv::CsvRow& row);
    double DueSeconds(size_t i) const;  // [wall s after start] when row i is due (--speed)

    CsvSourceOptions options_;
    csv::CsvFile file_;
    Bus bus_;
    StatusReporter status_;
    csv::MessageBuilder builder_;
    size_t next_ = 0;
    int64_t messages_ = 0;
    bool started_ = false;
    Clock::time_point start_{};
    Clock::time_point finished_{};
    Clock::time_point last_turn_{};  // --max: previous loop turn
    double tokens_ = 1.0;            // --max: messages that may go out now
};

}  // namespace gyrocal
