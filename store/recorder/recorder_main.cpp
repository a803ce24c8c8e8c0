// gyrocal-recorder: every message on the bus into SQLite.
//
// Threads: LCM's own receive thread reads the socket into LCM's (unbounded) queue; the main
// thread runs RunLoop: Bus::Handle dispatches each message to OnMessage, which only maps it to a
// row (RecordMapper: fingerprint, decode, run in force, seq gaps) and pushes it onto the
// AsyncWriter's bounded queue; the writer thread commits batches (every --batch-rows rows or
// --batch-ms ms, whichever first). On SIGINT/SIGTERM RunLoop returns, the messages LCM already
// received are dispatched (up to 2 s), the writer commits everything queued, the session is
// closed, and the process exits 0.
// Crash loss bound: a SIGKILL loses at most what arrived in the last --batch-ms plus one commit
// (default 200 ms + commit time); committed data and the file's integrity survive (WAL).
#include <glib.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "async_writer.hpp"
#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "bus/process_main.hpp"
#include "bus/shutdown.hpp"
#include "bus/status.hpp"
#include "gyrocal/version.hpp"
#include "open_run.hpp"
#include "record_mapper.hpp"
#include "writer_watch.hpp"
#include "writer.hpp"

namespace {

constexpr const char* kProcess = "gyrocal-recorder";

struct RecorderOptions {
    std::string db_path = "gyrocal.db";
    std::string lcm_url;          // "" = $GYROCAL_LCM_URL or the default
    std::string channels = ".*";  // LCM channel regex
    bool no_rates = false;
    size_t queue_rows = 100000;  // ~55 MB at most (544 bytes per held row)
    size_t batch_rows = 1000;
    int batch_ms = 200;
    static RecorderOptions Defaults() { return {}; }
};

// An LCM channel regex is checked the way LCM compiles it (GLib regex, anchored "^(...)$"), so a
// bad --channels is a bad option (exit 2) here, not a subscription that silently never matches.
CLI::Validator LcmChannelRegex() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
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
        },
        "REGEX");
}

int64_t WallUtime() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

class RecorderNode {
public:
    RecorderNode(const RecorderOptions& o, std::unique_ptr<gyrocal::store::StoreWriter> writer)
        : bus_(gyrocal::BusOptions{o.lcm_url}),
          status_(bus_, kProcess),
          store_(std::move(writer)),
          mapper_(gyrocal::record::MapperOptions{!o.no_rates},
                  gyrocal::record::OpenRunOnBus(store_->db(), bus_.url())),
          writer_(*store_, gyrocal::store::AsyncWriterOptions{
                               o.queue_rows, o.batch_rows, std::chrono::milliseconds(o.batch_ms)}),
          watch_(o.queue_rows) {
        store_->BeginSession(WallUtime(), mapper_.current_run());
        if (!mapper_.current_run().empty()) {
            SeedSeqs(mapper_.current_run());
            std::cerr << kProcess << ": continuing run '" << mapper_.current_run()
                      << "' (started on this bus, not stopped, in " << o.db_path << ")\n";
        }
        bus_.SubscribeRaw(o.channels, [this](const lcm::ReceiveBuffer& rbuf,
                                             const std::string& channel) {
            OnMessage(rbuf, channel);
        });
    }

    // Returns the exit code: 0 after a normal stop, 1 when the database failed.
    int Run() {
        gyrocal::RunLoop(bus_, status_, [this] { return Poll(); });
        // Stop requested: what LCM has already received is still recorded (bounded: 2 s).
        const auto drain_until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        while (!writer_.failed() && std::chrono::steady_clock::now() < drain_until &&
               bus_.Handle(std::chrono::milliseconds(0))) {
        }
        writer_.Stop();
        Publish();
        if (writer_.failed()) {
            const gyrocal::store::AsyncWriterStats s = writer_.stats();
            std::cerr << kProcess << ": error: " << writer_.error() << "\n";
            if (s.unwritten_rows > 0) {
                std::cerr << kProcess << ": error: " << s.unwritten_rows
                          << " received rows were not written: " << s.unwritten_summary << "\n";
            }
            return 1;
        }
        store_->EndSession(WallUtime());
        return 0;
    }

private:
    // Continuing a run: seq tracking resumes from the last stored sample of each stream, so the
    // samples lost by a crash and while down are counted as seq gaps of the run.
    void SeedSeqs(const std::string& run_id) {
        using Kind = gyrocal::store::StoreWriter::StreamSeq::Kind;
        for (const auto& s : store_->LastSeqs(run_id)) {
            if (s.kind == Kind::kEncoder) {
                mapper_.SeedSeq(std::string(gyrocal::channels::kEncoder), s.seq);
            } else if (s.kind == Kind::kChamberState) {
                mapper_.SeedSeq(std::string(gyrocal::channels::kChamberState), s.seq);
            } else if (gyrocal::channels::IsValidSensorId(s.sensor_id)) {
                mapper_.SeedSeq(gyrocal::channels::Gyro(s.sensor_id), s.seq);
            }
        }
    }

    void OnMessage(const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
        gyrocal::record::Mapped m = mapper_.Map(channel, rbuf.data,
                                                static_cast<int>(rbuf.data_size), rbuf.recv_utime);
        writer_.AddLoss(m.run_id, channel, m.loss);
        status_.AddSeqGaps(m.loss.seq_gaps);  // so the progress line shows what the recorder missed
        status_.AddDecodeErrors(m.loss.decode_errors);
        if (m.loss.decode_errors > 0) {
            status_.Reject("decode_error", "channel " + channel + ": known fingerprint " +
                                               "that does not decode; kept in raw_events");
        }
        if (m.row && !writer_.Push(std::move(*m.row), channel, m.essential)) {
            status_.AddQueueDrops(1);
        }
    }

    // Called by RunLoop between dispatches: counters to STATUS, stop on writer failure (a
    // storage fault is not one: the writer holds the rows and retries, WriterWatch reports it).
    bool Poll() {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_poll_ > std::chrono::milliseconds(250)) {
            last_poll_ = now;
            Publish();
        }
        return writer_.failed();
    }

    void Publish() {
        const auto report = watch_.Update(writer_.stats(), std::chrono::steady_clock::now());
        for (const auto& [name, value] : report.extras) status_.SetExtra(name, value);
        for (const auto& line : report.log) std::cerr << kProcess << ": " << line << "\n";
        const std::string state = writer_.failed() ? "failed" : report.state;
        if (state != status_.state()) {
            status_.set_state(state);
            status_.PublishNow();
        }
    }

    gyrocal::Bus bus_;
    gyrocal::StatusReporter status_;
    std::unique_ptr<gyrocal::store::StoreWriter> store_;
    gyrocal::record::RecordMapper mapper_;
    gyrocal::store::AsyncWriter writer_;
    gyrocal::record::WriterWatch watch_;
    std::chrono::steady_clock::time_point last_poll_{};
};

}  // namespace

int main(int argc, char** argv) {
    RecorderOptions o = RecorderOptions::Defaults();
    CLI::App app{
        "gyrocal-recorder: records every LCM message into an SQLite database (WAL, batched).\n"
        "Known types go to their tables, unknown ones to raw_events; runs follow RUN_EVENT.\n"
        "A SIGKILL loses at most the last --batch-ms of data (plus one commit).\n"
        "Database on a full disk, read-only or locked: STATUS state db_blocked:<fault> and a log\n"
        "line; received rows wait in memory (up to --queue-rows) and are written when it can\n"
        "again; rows beyond the bound are counted in losses.queue_drops by run and channel.\n"
        "Exit codes: 0 normal stop (SIGINT/SIGTERM), 1 runtime failure (database write, LCM),\n"
        "2 bad options (including a --db that cannot be opened or is not a gyrocal database).",
        "gyrocal-recorder"};
    app.add_option("--db", o.db_path, "SQLite database file (created when missing)");
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default $GYROCAL_LCM_URL or udpm default)");
    app.add_option("--channels", o.channels, "LCM channel regex to record")
        ->check(LcmChannelRegex())
        ->capture_default_str();
    app.add_flag("--no-rates", o.no_rates, "do not store RATE_* (compensated rate) messages");
    app.add_option("--queue-rows", o.queue_rows,
                   "rows held in memory (queued, or waiting for a blocked database) before dropping")
        ->check(CLI::Range(size_t{1000}, size_t{100000000}))->capture_default_str();
    app.add_option("--batch-rows", o.batch_rows, "commit every N rows")
        ->check(CLI::Range(size_t{1}, size_t{1000000}))->capture_default_str();
    app.add_option("--batch-ms", o.batch_ms, "commit at least every N ms (crash loss bound)")
        ->check(CLI::Range(1, 60000))->capture_default_str();
    // The options check themselves (CLI::Range, LcmChannelRegex); --db is checked by opening it.
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, kProcess)) return *exit_code;

    std::unique_ptr<gyrocal::store::StoreWriter> writer;
    try {
        writer = std::make_unique<gyrocal::store::StoreWriter>(
            o.db_path, gyrocal::store::WriterInfo{gyrocal::kSoftwareVersion, gyrocal::HostName(),
                                                  static_cast<int32_t>(getpid())});
    } catch (const std::exception& e) {
        std::cerr << kProcess << ": --db: " << e.what() << "\n";
        return 2;
    }
    try {
        gyrocal::InstallStopHandlers();
        RecorderNode node(o, std::move(writer));
        return node.Run();
    } catch (const std::exception& e) {
        std::cerr << kProcess << ": error: " << e.what() << "\n";
        return 1;
    }
}
