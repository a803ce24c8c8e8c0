#include "store/replay/replay_node.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <thread>
#include <variant>

#include "lcmtypes/process/shutdown.hpp"
#include "store/db/query.hpp"
#include "store/recorder/replay_source.hpp"

namespace gyrocal::replay {

namespace {

int64_t RecvUtimeOf(const db::Row& row) {
    return std::visit([](const auto& r) { return r.recv_utime; }, row);
}

}  // namespace

ReplayNode::ReplayNode(const ReplayOptions& o)
    : options_(o),
      db_(db::OpenForQuery(o.db_path)),
      reader_(*db_, o.run_id),
      bus_(bus::BusOptions{o.lcm_url}) {
    if (o.max) flow_ = std::make_unique<flow::FlowSource>(bus_, kReplayProcess, o.flow.Window());
}

void ReplayNode::WaitForRoom(int64_t recv_utime) {
    while (!process::StopRequested()) {
        flow_->Sync(recv_utime);
        const std::optional<int64_t> credit = flow_->Credit();
        if (!credit || *credit > 0) break;  // room, or nobody to wait for
        flow_->WaitForCredit(std::chrono::milliseconds(20));
    }
    for (const std::string& line : flow_->TakeReports())
        std::cerr << kReplayProcess << ": flow: " << line << "\n";
}

void ReplayNode::WaitUntilDue(int64_t recv_utime) {
    if (recv0_ < 0) recv0_ = recv_utime;
    if (options_.max) return;
    const auto due = wall0_ + std::chrono::microseconds(static_cast<int64_t>(
                                  static_cast<double>(recv_utime - recv0_) / options_.speed));
    // Sleep in short steps so SIGINT is honoured during long gaps.
    while (!process::StopRequested() && std::chrono::steady_clock::now() < due) {
        std::this_thread::sleep_until(
            std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(100)));
    }
}

int ReplayNode::Run() {
    if (flow_) flow_->Discover();
    wall0_ = std::chrono::steady_clock::now();
    int64_t last_recv = 0;
    while (!process::StopRequested()) {
        std::optional<db::Row> row = reader_.Next();
        if (!row) break;
        last_recv = RecvUtimeOf(*row);
        if (flow_) {
            WaitForRoom(last_recv);
        } else {
            WaitUntilDue(last_recv);
        }
        if (auto* ev = std::get_if<db::RunEventRow>(&*row); ev && !options_.as_run.empty()) {
            ev->run_id = options_.as_run;
        }
        const auto msg = recorder::EncodeForReplay(*row);
        if (!msg) continue;
        if (bus_.PublishRaw(msg->channel, msg->bytes.data(), static_cast<int>(msg->bytes.size()))) {
            ++published_;
        }
    }
    if (flow_ && !process::StopRequested() && flow_->paced_consumers() > 0 &&
        !flow_->Drain(last_recv))
        std::cerr << kReplayProcess << ": flow: not every consumer answered the end\n";
    std::cerr << kReplayProcess << ": published " << published_ << " messages of run '"
              << options_.run_id << "' (" << bus_.counters().publish_errors << " publish errors)\n";
    return bus_.counters().publish_errors == 0 ? 0 : 1;
}

}  // namespace gyrocal::replay
