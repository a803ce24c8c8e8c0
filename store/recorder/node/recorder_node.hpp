#pragma once
// gyrocal-recorder's node: every message on the bus into SQLite.
//
// Threads: LCM's own receive thread reads the socket into LCM's (unbounded) queue; the thread
// that calls Run() runs RunLoop: Bus::Handle dispatches each message to OnMessage, which only
// maps it to a row (RecordMapper: fingerprint, decode, run in force, seq gaps) and pushes it onto
// the AsyncWriter's bounded queue; the writer thread commits batches (every batch_rows rows or
// batch_ms ms, whichever first). On SIGINT/SIGTERM RunLoop returns and Finish() dispatches the
// messages LCM already received (up to 2 s), the writer commits everything queued and the
// session is closed. With --push-to, a run's end starts a `gyrocal push` process that the
// recorder never waits on (background_push.hpp).
// Crash loss bound: a SIGKILL loses at most what arrived in the last batch_ms plus one commit;
// committed data and the file's integrity survive (WAL).
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "store/db/async_writer.hpp"
#include "store/db/writer.hpp"
#include "store/recorder/node/background_push.hpp"
#include "store/recorder/record_mapper.hpp"
#include "store/recorder/writer_watch.hpp"

namespace gyrocal::recorder::node {

inline constexpr const char* kRecorderProcess = "gyrocal-recorder";

struct RecorderOptions {
    std::string db_path = "gyrocal.db";
    std::string lcm_url;          // "" = $GYROCAL_LCM_URL or the default
    std::string channels = ".*";  // LCM channel regex
    bool no_rates = false;
    size_t queue_rows = 100000;  // rows held in memory (544 bytes per held row)
    size_t batch_rows = 1000;
    int batch_ms = 200;
    std::string push_to;  // central database URL: push each run when it ends ("" = never)
    static RecorderOptions Defaults() { return {}; }
};

// "" when `text` compiles as LCM compiles a channel regex (GLib regex, anchored "^(...)$"), else
// why not and what would be valid; so a bad --channels is a bad option, not a subscription that
// silently never matches.
std::string ValidateLcmChannelRegex(const std::string& text);

// Opens (creating when missing) the database the recorder writes, as this process (software
// version, host, pid). Throws when it cannot be opened or is not a gyrocal database.
std::unique_ptr<db::StoreWriter> OpenRecorderDatabase(const std::string& db_path);

class RecorderNode {
public:
    // Throws BusError when LCM cannot be opened, store errors when the database fails.
    RecorderNode(const RecorderOptions& o, std::unique_ptr<db::StoreWriter> writer);
    // Until SIGINT/SIGTERM or a database failure, then Finish(). Returns the exit code: 0 after
    // a normal stop, 1 when the database failed.
    int Run();
    // Records what LCM has already received (bounded: 2 s), commits everything queued, closes
    // the session. Returns the exit code as Run() does.
    int Finish();
    // The node's bus: tests publish into it over memq://.
    bus::Bus& bus() { return bus_; }

private:
    void SeedSeqs(const std::string& run_id);
    void OnMessage(const lcm::ReceiveBuffer& rbuf, const std::string& channel);
    bool Poll();
    void Publish();

    bus::Bus bus_;
    process::StatusReporter status_;
    std::unique_ptr<db::StoreWriter> store_;
    RecordMapper mapper_;
    db::AsyncWriter writer_;
    WriterWatch watch_;
    BackgroundPush push_;
    std::chrono::steady_clock::time_point last_poll_{};
};

}  // namespace gyrocal::recorder::node
