#include "store/recorder/node/recorder_node.hpp"

#include <glib.h>
#include <unistd.h>

#include <iostream>
#include <variant>

#include "gyrocal/version.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "store/recorder/open_run.hpp"

namespace gyrocal::recorder::node {

std::string ValidateLcmChannelRegex(const std::string& text) {
    const std::string anchored = "^" + text + "$";
    GError* error = nullptr;
    GRegex* re = g_regex_new(anchored.c_str(), static_cast<GRegexCompileFlags>(0),
                             static_cast<GRegexMatchFlags>(0), &error);
    if (re) {
        g_regex_unref(re);
        return "";
    }
    std::string why = error ? error->message : "does not compile";
    if (error) g_error_free(error);
    return "'" + text + "' is not a valid channel regex (" + why +
           "); e.g. '.*' or 'GYRO_.*|RUN_EVENT'";
}

std::unique_ptr<db::StoreWriter> OpenRecorderDatabase(const std::string& db_path) {
    return std::make_unique<db::StoreWriter>(
        db_path,
        db::WriterInfo{kSoftwareVersion, process::HostName(), static_cast<int32_t>(getpid())});
}

RecorderNode::RecorderNode(const RecorderOptions& o, std::unique_ptr<db::StoreWriter> writer)
    : bus_(bus::BusOptions{o.lcm_url}),
      status_(bus_, kRecorderProcess),
      store_(std::move(writer)),
      mapper_(MapperOptions{!o.no_rates}, OpenRunOnBus(store_->db(), bus_.url())),
      writer_(*store_, db::AsyncWriterOptions{o.queue_rows, o.batch_rows,
                                              std::chrono::milliseconds(o.batch_ms)}),
      watch_(o.queue_rows),
      push_(o.push_to, o.db_path) {
    store_->BeginSession(bus::WallClockUtime(), mapper_.current_run());
    if (!mapper_.current_run().empty()) {
        SeedSeqs(mapper_.current_run());
        std::cerr << kRecorderProcess << ": continuing run '" << mapper_.current_run()
                  << "' (started on this bus, not stopped, in " << o.db_path << ")\n";
    }
    bus_.SubscribeRaw(o.channels, [this](const lcm::ReceiveBuffer& rbuf,
                                         const std::string& channel) { OnMessage(rbuf, channel); });
    // A row is handled once its writer has it, but "has it" must not outrun the disk: a source
    // is answered only while the write queue is at most half full, so a slow disk slows the
    // source instead of filling the queue to its drop bound.
    const size_t half = o.queue_rows / 2;
    status_.acker().SetGate(
        [this, half] { return static_cast<size_t>(writer_.stats().held_rows) <= half; });
}

int RecorderNode::Run() {
    process::RunLoop(bus_, status_, [this] { return Poll(); });
    return Finish();
}

int RecorderNode::Finish() {
    // Stop requested: what LCM has already received is still recorded (bounded: 2 s).
    const auto drain_until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!writer_.failed() && std::chrono::steady_clock::now() < drain_until &&
           bus_.Handle(std::chrono::milliseconds(0))) {
    }
    writer_.Stop();
    for (const auto& line : push_.Poll()) std::cerr << kRecorderProcess << ": " << line << "\n";
    Publish();
    if (writer_.failed()) {
        const db::AsyncWriterStats s = writer_.stats();
        std::cerr << kRecorderProcess << ": error: " << writer_.error() << "\n";
        if (s.unwritten_rows > 0) {
            std::cerr << kRecorderProcess << ": error: " << s.unwritten_rows
                      << " received rows were not written: " << s.unwritten_summary << "\n";
        }
        return 1;
    }
    store_->EndSession(bus::WallClockUtime());
    return 0;
}

// Continuing a run: seq tracking resumes from the last stored sample of each stream, so the
// samples lost by a crash and while down are counted as seq gaps of the run.
void RecorderNode::SeedSeqs(const std::string& run_id) {
    using Kind = db::StoreWriter::StreamSeq::Kind;
    for (const auto& s : store_->LastSeqs(run_id)) {
        if (s.kind == Kind::kEncoder) {
            mapper_.SeedSeq(std::string(channels::kEncoder), s.seq);
        } else if (s.kind == Kind::kChamberState) {
            mapper_.SeedSeq(std::string(channels::kChamberState), s.seq);
        } else if (channels::IsValidSensorId(s.sensor_id)) {
            mapper_.SeedSeq(channels::Gyro(s.sensor_id), s.seq);
        }
    }
}

void RecorderNode::OnMessage(const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
    Mapped m = mapper_.Map(channel, rbuf.data, static_cast<int>(rbuf.data_size), rbuf.recv_utime);
    writer_.AddLoss(m.run_id, channel, m.loss);
    status_.AddSeqGaps(m.loss.seq_gaps);  // so the progress line shows what the recorder missed
    status_.AddDecodeErrors(m.loss.decode_errors);
    if (m.loss.decode_errors > 0) {
        status_.Reject("decode_error", "channel " + channel + ": known fingerprint " +
                                           "that does not decode; kept in raw_events");
    }
    if (push_.enabled() && m.row) {  // a run's end: pushed once its stop is committed
        if (const auto* e = std::get_if<db::RunEventRow>(&*m.row);
            e && (e->event == "stop" || e->event == "abort"))
            push_.RunEnded(e->run_id);
    }
    if (m.row && !writer_.Push(std::move(*m.row), channel, m.essential)) {
        status_.AddQueueDrops(1);
    }
    for (db::Row& row : m.more) {
        if (!writer_.Push(std::move(row), channel, m.essential)) status_.AddQueueDrops(1);
    }
}

// Called by RunLoop between dispatches: counters to STATUS, stop on writer failure (a
// storage fault is not one: the writer holds the rows and retries, WriterWatch reports it).
bool RecorderNode::Poll() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_poll_ > std::chrono::milliseconds(250)) {
        last_poll_ = now;
        Publish();
        for (const auto& line : push_.Poll()) std::cerr << kRecorderProcess << ": " << line << "\n";
    }
    return writer_.failed();
}

void RecorderNode::Publish() {
    const auto report = watch_.Update(writer_.stats(), std::chrono::steady_clock::now());
    for (const auto& [name, value] : report.extras) status_.SetExtra(name, value);
    for (const auto& line : report.log) std::cerr << kRecorderProcess << ": " << line << "\n";
    const std::string state = writer_.failed() ? "failed" : report.state;
    if (state != status_.state()) {
        status_.set_state(state);
        status_.PublishNow();
    }
}

}  // namespace gyrocal::recorder::node
