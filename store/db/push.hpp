#pragma once
// Store and forward: a station's runs, from its SQLite file to the lab's central PostgreSQL
// database (central_db.hpp), every table of the run, raw samples included.
//
// Exactly once: each run is pushed in ONE central transaction (COPY for the bulk), under an
// advisory lock on its run id, so a reader sees all of a push or none of it, and two pushes of the
// same run (two shells, the recorder's background push) wait for each other. A push that is cut
// off (killed, network down, server restarted) leaves nothing at the centre; the next one does
// the run again. What is already at the centre is found there, per table, from the ids: a run's
// rows carry ids run_key * 10^12 + station id, so the highest id of a table in the run's range is
// how far that table was pushed, and only the station's rows above it are sent (a run that gained
// rows since, e.g. a new analysis, sends just those). Pushing twice changes nothing.
//
// What a station records: each push that committed is a row of its `pushes` table (central URL
// without credentials, the run's outcome and "mark" then); `gyrocal push` with no run sends the
// finished runs whose mark differs from their last push to that centre (new runs, runs analysed
// again). With `include_open`, runs still being recorded are sent up to what is committed; when
// one finishes, its next push brings the rest and updates its `runs` row and loss counters, the
// only rows a station ever changes (that needs UPDATE on runs and losses at the centre; finished
// runs need only INSERT and SELECT).
//
// Station identity: the centre's run_origins row of each run names the host, the station's file
// and the software version that first pushed it. A run id that is already at the centre as a
// different run (other start time or host) is refused for that run, never merged.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace gyrocal::db {

struct PushOptions {
    std::string station_db;            // the station's SQLite file
    std::string central_url;           // postgresql://... (credentials as libpq reads them)
    std::vector<std::string> run_ids;  // empty: every run with something new for this centre
    bool include_open = false;         // also runs still being recorded (up to what is committed)
    std::string software_version;      // recorded with each run at the centre
    std::string host;                  // the station's host name ("" = this host's)
    // Called with a line of progress per run (may be empty).
    std::function<void(const std::string&)> log;
};

struct RunPush {
    std::string run_id;
    bool ok = false;
    int64_t rows_added = 0, rows_updated = 0, samples_added = 0;  // [count]
    double seconds = 0;                                           // [s] wall time of the push
    std::string error;  // why it was not pushed (one line), when !ok
};

struct PushReport {
    std::string central;  // URL without credentials
    std::vector<RunPush> runs;
    int failed() const {
        int n = 0;
        for (const RunPush& r : runs) n += r.ok ? 0 : 1;
        return n;
    }
};

// Pushes the runs. Throws StoreError / CentralError (one line, nothing written anywhere) for what
// stops everything before a run is sent: the station file is not a gyrocal database, a run named
// does not exist or is still open without include_open, the centre cannot be reached, refuses the
// credentials, is not a gyrocal database or has an older schema than this station. A connection
// lost during a run also throws (that run is not at the centre; runs pushed before it are, and
// are recorded). A run refused on its own (another run of that id at the centre) is a RunPush
// with ok false, and the others go on.
PushReport Push(const PushOptions& options);

// Waits (polling the station file every 200 ms) until run `run_id` has ended there, i.e. its stop
// or abort is committed; false when it has not after `timeout_s` (or the run never appears).
bool WaitUntilEnded(const std::string& station_db, const std::string& run_id, double timeout_s);

// The runs `gyrocal push` with no run would send from `station_db` to `central_url`, in order.
std::vector<std::string> RunsToPush(const std::string& station_db, const std::string& central_url,
                                    bool include_open);

}  // namespace gyrocal::db
