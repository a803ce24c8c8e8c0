#include "producers/log_source/log_source_node.hpp"

#include <algorithm>
#include <iostream>
#include <thread>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::log_source {

namespace {
constexpr const char* kProcess = "gyrocal-log-source";

bool IsFlowControl(const std::string& channel) {
    return channel == channels::kFlowMark || channel == channels::kFlowAck;
}
}  // namespace

std::string LogSourceOptions::Validate() const {
    if (!max && !(speed > 0.0 && speed <= 1e6))
        return "--speed " + text::Sig(speed) +
               " is out of range; valid: > 0 and <= 1e6 recorded seconds per wall second (or "
               "--max)";
    if (!(drain_s >= 0.0 && drain_s <= 60.0))
        return "--drain-s " + text::Sig(drain_s) + " is out of range; valid: 0 to 60 s";
    try {
        std::regex re(channels);
    } catch (const std::regex_error& e) {
        return "--channels '" + channels + "' is not a valid regular expression (" + e.what() +
               "); e.g. 'GYRO_.*|ENCODER|CHAMBER_STATE|RUN_EVENT'";
    }
    return flow.Validate();
}

int64_t CheckLog(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("--file '" + file + "' cannot be opened");
    log_source::LogReader reader(in, file);
    int64_t n = 0;
    while (reader.Next()) ++n;
    return n;
}

LogSourceNode::LogSourceNode(const LogSourceOptions& options, int64_t events)
    : options_(options),
      channels_(options.channels),
      in_(options.file, std::ios::binary),
      reader_(in_, options.file),
      bus_(bus::BusOptions{options.lcm_url}),
      status_(bus_, kProcess),
      events_total_(events) {
    if (!in_) throw std::runtime_error("--file '" + options.file + "' cannot be read again");
    if (options_.max)
        flow_ = std::make_unique<flow::FlowSource>(bus_, kProcess, options_.flow.Window());
    status_.SetExtra("events_total", static_cast<double>(events_total_));
    Fetch();
}

void LogSourceNode::Fetch() {
    next_.reset();
    try {
        while (std::optional<log_source::Event> e = reader_.Next()) {
            if (IsFlowControl(e->channel) || !std::regex_match(e->channel, channels_)) {
                ++skipped_;
                continue;
            }
            next_ = std::move(e);
            return;
        }
    } catch (const log_source::LogError& e) {
        error_ = e.what();  // the file changed since it was checked
    }
}

void LogSourceNode::Publish(const log_source::Event& e) {
    if (first_utime_ < 0) first_utime_ = e.utime;
    last_utime_ = e.utime;
    if (bus_.PublishRaw(e.channel, e.data.data(), static_cast<int>(e.data.size()))) ++published_;
}

bool LogSourceNode::Step() {
    const auto now = Clock::now();
    if (!started_) {
        started_ = true;
        start_ = now;
        status_.set_state("replaying");
        if (flow_) flow_->Discover();
    }
    if (next_) {
        const auto until = now + std::chrono::milliseconds(20);
        if (flow_) {
            flow_->Sync(last_utime_);
            std::optional<int64_t> credit = flow_->Credit();
            if (credit && *credit <= 0) flow_->WaitForCredit(std::chrono::milliseconds(20));
            // With nobody answering, --max has no timing at all (as lcm-logplayer has none).
            while (next_ && (!credit || *credit > 0) && Clock::now() < until) {
                Publish(*next_);
                Fetch();
                flow_->Sync(last_utime_);
                credit = flow_->Credit();
            }
            for (const auto& [name, value] : flow_->Extras()) status_.SetExtra(name, value);
            for (const std::string& line : flow_->TakeReports())
                std::cerr << kProcess << ": flow: " << line << "\n";
        } else {
            const double elapsed_s = std::chrono::duration<double>(now - start_).count();
            const int64_t first = first_utime_ < 0 ? next_->utime : first_utime_;
            auto due_s = [&] { return (next_->utime - first) * 1e-6 / options_.speed; };
            while (next_ && due_s() <= elapsed_s && Clock::now() < until) {
                Publish(*next_);
                Fetch();
            }
            if (next_)
                std::this_thread::sleep_for(
                    std::chrono::duration<double>(std::clamp(due_s() - elapsed_s, 0.0, 0.02)));
        }
        status_.SetExtra("events_published", static_cast<double>(published_));
        if (!next_) finished_ = Clock::now();
        return false;
    }
    if (flow_ && flow_->paced_consumers() > 0) {
        if (!flow_->Drain(last_utime_))
            std::cerr << kProcess << ": flow: not every consumer answered the end\n";
        return true;
    }
    if (Clock::now() - finished_ >= std::chrono::duration<double>(options_.drain_s)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return false;
}

int LogSourceNode::Run() {
    process::RunLoop(
        bus_, status_, [this] { return Step(); }, std::chrono::milliseconds(0));
    std::cerr << kProcess << ": published " << published_ << " of " << events_total_
              << " events from " << options_.file << " (" << skipped_ << " not on --channels "
              << "or flow control)";
    if (process::StopRequested() && next_) std::cerr << "; stopped by signal";
    std::cerr << "\n";
    if (!error_.empty()) {
        std::cerr << kProcess << ": error: " << error_ << "\n";
        return 1;
    }
    if (bus_.counters().publish_errors > 0) {
        std::cerr << kProcess << ": error: " << bus_.counters().publish_errors
                  << " messages could not be sent (LCM publish failed)\n";
        return 1;
    }
    return 0;
}

}  // namespace gyrocal::log_source
