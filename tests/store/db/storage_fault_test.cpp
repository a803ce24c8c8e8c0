// The batching writer on storage faults, with real SQLite files and no root: a database locked
// by another writer (another connection holding the write lock), the memory bound reached while
// it lasts, a stop while it still lasts, and a database file removed under the writer. The
// disk-full and read-only file system cases need mounts: tests/store/recorder/storage_fault_test.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>

#include "store/db/async_writer.hpp"
#include "store/db/writer.hpp"
#include "tests/store/scratch_db.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::db {
namespace {

using namespace std::chrono_literals;

using testing::Count;
using testing::FreshDbPath;

GyroRow Sample(const std::string& run, const std::string& sensor, int64_t seq) {
    GyroRow g;
    g.run_id = run;
    g.sensor_id = sensor;
    g.seq = seq;
    g.utime = 1000 + seq;
    g.gyro_v = 2.5;
    return g;
}

// Polls `done` until true or 10 s (generous: the writer retries every 100 ms here).
bool WaitFor(const std::function<bool()>& done) { return testing::WaitUntil(done, 10s, 5ms); }

AsyncWriterOptions Fast(size_t queue_rows) {
    AsyncWriterOptions o;
    o.queue_rows = queue_rows;
    o.batch_rows = 10;
    o.batch_interval = 20ms;
    o.retry_interval = 100ms;
    return o;
}

// Another connection holding the write lock of the database at `path` until Release.
class WriteLock {
public:
    explicit WriteLock(const std::string& path) : db_(path, Db::Mode::kReadWrite) {
        db_.Exec("BEGIN IMMEDIATE");
    }
    // Ends its transaction (COMMIT or ROLLBACK).
    void Release(const char* how) { db_.Exec(how); }

private:
    Db db_;
};

// A database locked by another writer, and a batching writer on it with room for `queue_rows`.
struct LockedDatabase {
    LockedDatabase(const std::string& name, size_t queue_rows)
        : path(FreshDbPath(name)), writer(path, {}), lock(path), aw(writer, Fast(queue_rows)) {}
    std::string path;
    StoreWriter writer;
    WriteLock lock;
    AsyncWriter aw;
};

TEST(StorageFault, ALockedDatabaseHoldsEveryRowAndWritesThemWhenReleased) {
    LockedDatabase db("locked.db", 100000);
    // Run R9 exists only through its samples: the bare runs row is made in the failed
    // transaction first, so the retry must make it again (not trust a cache the rollback undid).
    for (int64_t s = 0; s < 500; ++s) ASSERT_TRUE(db.aw.Push(Sample("R9", "S01", s), "GYRO_S01"));
    ASSERT_TRUE(WaitFor([&] { return db.aw.stats().blocked; }));
    AsyncWriterStats s = db.aw.stats();
    EXPECT_EQ(s.blocked_reason, "locked by another writer");
    EXPECT_NE(s.blocked_error.find("locked"), std::string::npos) << s.blocked_error;
    EXPECT_EQ(s.held_rows, 500);
    EXPECT_EQ(s.written, 0);
    EXPECT_EQ(s.dropped, 0);

    db.lock.Release("COMMIT");
    ASSERT_TRUE(WaitFor([&] { return db.aw.stats().written == 500; }));
    s = db.aw.stats();
    EXPECT_FALSE(s.blocked);
    EXPECT_EQ(s.held_rows, 0);
    EXPECT_EQ(s.fault_episodes, 1);
    EXPECT_GE(s.failed_writes, 1);
    db.aw.Stop();
    ASSERT_FALSE(db.aw.failed()) << db.aw.error();
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM gyro_samples WHERE run_id = 'R9'"), 500);
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM runs WHERE run_id = 'R9'"), 1);
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM sensors WHERE sensor_id = 'S01'"), 1);
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM losses"), 0);
}

TEST(StorageFault, AtTheMemoryBoundRowsAreDroppedAndCountedPerRunAndChannel) {
    LockedDatabase db("bound.db", 200);
    std::map<std::string, int64_t> refused;  // by channel
    for (int64_t s = 0; s < 150; ++s) {
        for (const char* id : {"S01", "S02"}) {
            const std::string channel = std::string("GYRO_") + id;
            if (!db.aw.Push(Sample("R1", id, s), channel)) ++refused[channel];
        }
    }
    RunEventRow stop;  // essential: kept beyond the bound
    stop.run_id = "R1";
    stop.event = "stop";
    EXPECT_TRUE(db.aw.Push(stop, "RUN_EVENT", /*essential=*/true));
    ASSERT_TRUE(WaitFor([&] { return db.aw.stats().blocked; }));
    EXPECT_EQ(db.aw.stats().held_rows, 201);
    EXPECT_EQ(db.aw.stats().dropped, 100);
    EXPECT_EQ(refused["GYRO_S01"] + refused["GYRO_S02"], 100);

    db.lock.Release("COMMIT");
    db.aw.Stop();
    ASSERT_FALSE(db.aw.failed()) << db.aw.error();
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM gyro_samples"), 200);
    for (const auto& [channel, n] : refused) {
        EXPECT_EQ(Count(db.path,
                        "SELECT queue_drops FROM losses WHERE run_id = 'R1' AND "
                        "channel = '" +
                            channel + "'"),
                  n)
            << channel;
    }
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM runs WHERE run_id = 'R1' AND outcome = 'stop'"),
              1);
}

TEST(StorageFault, AStopWhileStillBlockedGivesUpAndSaysWhatWasNotWritten) {
    LockedDatabase db("stop_blocked.db", 100000);
    for (int64_t s = 0; s < 30; ++s) ASSERT_TRUE(db.aw.Push(Sample("R1", "S01", s), "GYRO_S01"));
    StatusRow st;
    st.run_id = "R1";
    ASSERT_TRUE(db.aw.Push(st, "STATUS"));
    ASSERT_TRUE(WaitFor([&] { return db.aw.stats().blocked; }));
    db.aw.Stop();  // one last attempt, still locked
    EXPECT_TRUE(db.aw.failed());
    EXPECT_NE(db.aw.error().find("still cannot be written at stop (locked by another writer)"),
              std::string::npos)
        << db.aw.error();
    const AsyncWriterStats s = db.aw.stats();
    EXPECT_EQ(s.unwritten_rows, 31);
    EXPECT_EQ(s.unwritten_summary, "R1 gyro_samples 30, R1 status 1");
    db.lock.Release("ROLLBACK");
    EXPECT_EQ(Count(db.path, "SELECT count(*) FROM gyro_samples"), 0);
}

TEST(StorageFault, ADatabaseFileRemovedUnderTheWriterIsCreatedAgainAndWritten) {
    const std::string path = FreshDbPath("removed.db");
    StoreWriter w(path, {});
    AsyncWriter aw(w, Fast(100000));
    for (int64_t s = 0; s < 10; ++s) ASSERT_TRUE(aw.Push(Sample("R1", "S01", s), "GYRO_S01"));
    ASSERT_TRUE(WaitFor([&] { return aw.stats().written == 10; }));
    for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(path + ext);
    for (int64_t s = 10; s < 20; ++s) ASSERT_TRUE(aw.Push(Sample("R1", "S01", s), "GYRO_S01"));
    ASSERT_TRUE(WaitFor([&] { return aw.stats().written == 20; }));
    aw.Stop();
    ASSERT_FALSE(aw.failed()) << aw.error();
    // What was committed went with the removed file; what came after is in the new one.
    EXPECT_EQ(Count(path, "SELECT count(*) FROM gyro_samples WHERE seq >= 10"), 10);
    EXPECT_EQ(aw.stats().fault_episodes, 1);
}

}  // namespace
}  // namespace gyrocal::db
