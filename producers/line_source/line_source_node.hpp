#pragma once
// The live line-stream process: a DAQ or microcontroller prints the CSV columns as text lines
// (first line: the header) on stdin, a serial device or a FIFO; each valid line is published
// like a CSV row. A live stream cannot stop for a bad line: it is skipped whole, counted
// (STATUS rejected / lines_bad) and warned about at most once a second, naming its line number.
//
// Threads: one. Run() is RunLoop with a zero poll; each turn waits up to 50 ms for input
// (poll on the fd) and publishes the complete lines. End of input ends it (exit 0).
//
// --flow (a stream that is not live: a file or a pipe from another program): input is read only
// while every consumer on the bus has room (flow control, lcmtypes/flow), so a fast writer is
// held back by its pipe instead of flooding the bus. A live DAQ is never held back: no --flow.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/bus/sample_batcher.hpp"
#include "lcmtypes/flow/flow_source.hpp"
#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/status.hpp"
#include "producers/csv/conversion_options.hpp"
#include "producers/csv/row_messages.hpp"
#include "producers/line_source/line_input.hpp"
#include "producers/line_source/line_stream.hpp"

namespace gyrocal::line_source {

enum class TimeSource { kStream, kWall };

struct LineSourceOptions {
    std::string device;  // "" = stdin
    std::string lcm_url;
    TimeSource time = TimeSource::kStream;
    double drain_s = 0.2;  // [s] after end of input (without consumers answering)
    bool flow = false;     // read only while the consumers keep up (not for live streams)
    process::SourceFlowOptions flow_options = process::SourceFlowOptions::Defaults();
    csv::ConversionOptions conversion = csv::ConversionOptions::Defaults();
    static LineSourceOptions Defaults() { return {}; }
    std::string Validate() const;
};

class LineSourceNode {
public:
    LineSourceNode(const LineSourceOptions& options, std::unique_ptr<LineInput> input);
    // 0 at end of input or on SIGINT/SIGTERM; 1 on a read error or a stream without a header.
    int Run();

    // In-process use (tests over memq://): the node's bus, to subscribe to what it publishes
    // (Handle it after Run() for the last messages), and its counts.
    bus::Bus& bus() { return bus_; }
    int64_t rows_published() const { return published_rows_; }
    int64_t bad_lines() const { return bad_lines_; }

private:
    bool Step();
    bool AtEnd();  // end of input: the last answers (--flow) or --drain-s
    void HandleLine(const InputLine& line);
    int64_t Utime(const csv::CsvRow& row);

    LineSourceOptions options_;
    std::unique_ptr<LineInput> input_;
    bus::Bus bus_;
    process::StatusReporter status_;
    LineStream stream_;
    csv::MessageBuilder builder_;
    bus::SampleBatcher batcher_;
    std::unique_ptr<flow::FlowSource> flow_;  // --flow
    int64_t last_utime_ = 0;
    int64_t published_rows_ = 0;
    int64_t bad_lines_ = 0;
    int64_t last_wall_utime_ = 0;
    bool eof_ = false;
    std::string fatal_;
};

}  // namespace gyrocal::line_source
