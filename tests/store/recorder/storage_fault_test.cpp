// The real gyrocal-recorder on storage faults, over UDP multicast (ports 7850-7859):
// - the database locked by another writer (no root needed);
// - the memory bound reached while it is locked: what it had to drop is counted in losses;
// - a full disk: a 4 MB tmpfs filled up under it (root: mount);
// - a read-only database file: ext4 on a loop device, the files made immutable (root: mount,
//   chattr), the only way to make a file a process already has open refuse writes and then
//   accept them again;
// - started on a read-only file system: a clear error and exit 2 (root: mount).
// In each the recorder must say so on STATUS (state db_blocked:<fault>) and in its log, hold
// the rows in memory, write them when it can, and lose nothing it could have kept.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "lcmtypes/channels/channels.hpp"
#include "store/db/writer.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/store/recorder/recorder_harness.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A file system of our own for one test, unmounted (and its loop device freed) at the end.
class ScratchMount {
public:
    // Each returns "" when mounted, else why not (for GTEST_SKIP).
    std::string MountTmpfs(const std::string& name, int size_kb) {
        if (::geteuid() != 0) return "needs root to mount a tmpfs (CI runs as root)";
        MakeDir(name);
        return Mount("mount -t tmpfs -o size=" + std::to_string(size_kb) + "k gyrocal_test " +
                     dir_);
    }
    std::string MountExt4(const std::string& name, int size_mb) {
        if (::geteuid() != 0)
            return "needs root to mount a loop device and chattr (CI runs as root)";
        MakeDir(name);
        image_ = dir_ + ".img";
        const std::string why = Run("truncate -s " + std::to_string(size_mb) + "M " + image_ +
                                    " && mkfs.ext4 -q -F " + image_);
        return why.empty() ? Mount("mount -o loop " + image_ + " " + dir_) : why;
    }
    ~ScratchMount() {
        if (mounted_) Run("umount " + dir_);
        if (!image_.empty()) fs::remove(image_);
        if (!dir_.empty()) fs::remove(dir_);
    }
    const std::string& dir() const { return dir_; }

    // Runs a shell command; "" when it succeeded, else which command failed.
    static std::string Run(const std::string& cmd) {
        return std::system((cmd + " >/dev/null 2>&1").c_str()) == 0 ? "" : "failed: " + cmd;
    }

private:
    void MakeDir(const std::string& name) {
        dir_ = (fs::temp_directory_path() /
                ("gyrocal_fault_" + name + "_" + std::to_string(::getpid())))
                   .string();
        fs::create_directories(dir_);
    }
    std::string Mount(const std::string& cmd) {
        std::string why = Run(cmd);
        mounted_ = why.empty();
        if (!mounted_) why += " (mounting needs root and a kernel/container that allows it)";
        return why;
    }

    std::string dir_, image_;
    bool mounted_ = false;
};

// The recorder's STATUS as it changes: every state seen, and the latest extras.
struct RecorderStatus {
    std::set<std::string> states;
    std::string state;
    std::map<std::string, double> extra;
};

class Fault : public ::testing::Test {
protected:
    void Start(const std::string& db, int port, std::vector<std::string> extra = {}) {
        db_ = db;
        // The log is kept off the faulty file system (a full disk would swallow it).
        log_ = FreshDbPath("fault_" + std::to_string(port) + ".err");
        bus_ = std::make_unique<bus::Bus>(bus::BusOptions{UrlForPort(port)});
        std::vector<std::string> argv = {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder",
                                         "--db",
                                         db,
                                         "--lcm-url",
                                         UrlForPort(port),
                                         "--batch-ms",
                                         "50"};
        argv.insert(argv.end(), extra.begin(), extra.end());
        rec_.emplace(argv, "", log_);
        ASSERT_TRUE(WaitForRecorder(*bus_, rec_->pid(), 10s));
        const int pid = rec_->pid();
        bus_->Subscribe<status_t>(std::string(channels::kStatus),
                                  [this, pid](const status_t& s, const std::string&) {
                                      if (s.process != "gyrocal-recorder" || s.pid != pid) return;
                                      status_.states.insert(s.state);
                                      status_.state = s.state;
                                      for (size_t i = 0; i < s.extra_names.size(); ++i) {
                                          status_.extra[s.extra_names[i]] = s.extra_values[i];
                                      }
                                  });
        ASSERT_TRUE(
            bus_->Publish(std::string(channels::kRunEvent), RunEvent("RF", "start", {"K"})));
    }

    // The recorder on `db`, with its first 200 samples stored before a fault is made.
    void StartAndStore(const std::string& db, int port) {
        Start(db, port);
        Publish(200);
        ExpectAllStored();
    }

    // Publishes n samples of sensor K (about 2000/s, handling STATUS meanwhile).
    void Publish(int64_t n) {
        for (int64_t i = 0; i < n; ++i) {
            ASSERT_TRUE(bus_->Publish(channels::Gyro("K"), Gyro("K", seq_++)));
            if (seq_ % 4 == 0) bus_->Handle(1ms);
        }
    }

    // Handles STATUS until `done` or the deadline; true when done.
    bool WaitStatus(const std::function<bool()>& done, std::chrono::seconds limit = 20s) {
        const auto end = Clock::now() + limit;
        while (!done() && Clock::now() < end) bus_->Handle(20ms);
        return done();
    }

    int64_t Stored() { return Count(db_, "SELECT count(*) FROM gyro_samples WHERE run_id = 'RF'"); }

    // Every sample published so far committed (bounded wait).
    void ExpectAllStored() {
        EXPECT_EQ(
            WaitForCount(db_, "SELECT count(*) FROM gyro_samples WHERE run_id = 'RF'", seq_, 30s),
            seq_);
    }

    // Once the fault is gone: every held row written and recording again; then StopAndCheck.
    void ExpectRecoveredThenStop(const std::string& fault) {
        ExpectAllStored();
        EXPECT_TRUE(WaitStatus([&] { return status_.state == "recording"; }));
        StopAndCheck(fault);
    }

    // SIGTERM: exit 0, the log says the fault began and ended, the file is intact.
    void StopAndCheck(const std::string& fault) {
        const launch::ExitStatus st = rec_->Stop(10s);
        EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
        const std::string log = launch::ReadLog(log_);
        EXPECT_NE(log.find("database writes fail (" + fault + ")"), std::string::npos) << log;
        EXPECT_NE(log.find("database writable again after"), std::string::npos) << log;
        EXPECT_EQ(Count(db_,
                        "SELECT count(*) FROM pragma_integrity_check WHERE integrity_check "
                        "= 'ok'"),
                  1);
        EXPECT_EQ(Count(db_,
                        "SELECT count(*) FROM losses WHERE run_id = 'RF' AND "
                        "(queue_drops > 0 OR seq_gaps > 0)"),
                  0);
    }

    std::string db_, log_;
    std::unique_ptr<bus::Bus> bus_;
    std::optional<launch::ChildProcess> rec_;
    RecorderStatus status_;
    int64_t seq_ = 0;
};

TEST_F(Fault, LockedByAnotherWriterHoldsRowsAndWritesThemWhenReleased) {
    StartAndStore(FreshDbPath("fault_locked.db"), 7850);
    {
        db::Db blocker(db_, db::Db::Mode::kReadWrite);
        blocker.Exec("BEGIN IMMEDIATE");  // as another writer would, e.g. a long import
        Publish(2000);
        ASSERT_TRUE(WaitStatus([&] {
            return status_.state == "db_blocked:locked_by_another_writer";
        })) << "state "
            << status_.state;
        EXPECT_GT(status_.extra["held_rows"], 0);
        Publish(500);  // still arriving while blocked
        EXPECT_EQ(Stored(), 200);
        blocker.Exec("COMMIT");
    }
    ExpectRecoveredThenStop("locked by another writer");
}

TEST_F(Fault, AtTheMemoryBoundWhatIsDroppedIsCountedInLosses) {
    Start(FreshDbPath("fault_bound.db"), 7851, {"--queue-rows", "1000"});
    Publish(100);
    ExpectAllStored();
    db::Db blocker(db_, db::Db::Mode::kReadWrite);
    blocker.Exec("BEGIN IMMEDIATE");
    Publish(3000);
    ASSERT_TRUE(WaitStatus([&] { return status_.extra["rows_dropped"] > 0; }));
    blocker.Exec("COMMIT");
    // Held rows written out, not only the state word: a write still inside SQLite's busy wait
    // when the lock goes never reports a fault, so "recording" alone would let the next samples
    // arrive at a full queue.
    ASSERT_TRUE(WaitStatus(
        [&] { return status_.state == "recording" && status_.extra["held_rows"] == 0; }));
    const int64_t after = seq_;
    Publish(10);  // after the release: a lost UDP packet before these shows as a seq gap
    const int64_t published = seq_;
    // These have room again: wait until they are committed, so none is still on its way at stop.
    EXPECT_EQ(
        WaitForCount(db_, "SELECT count(*) FROM gyro_samples WHERE seq >= " + std::to_string(after),
                     10, 30s),
        10);
    EXPECT_EQ(rec_->Stop(10s).code, 0);
    // Every sample is stored or counted: dropped at the bound (queue_drops) or, had the network
    // lost one, as a seq gap. The bound held: at most --queue-rows rows were kept meanwhile.
    const int64_t stored = Stored();
    const int64_t dropped = Count(db_,
                                  "SELECT coalesce(sum(queue_drops), 0) FROM losses WHERE "
                                  "run_id = 'RF' AND channel = 'GYRO_K'");
    const int64_t gaps = Count(db_,
                               "SELECT coalesce(sum(seq_gaps), 0) FROM losses WHERE "
                               "run_id = 'RF' AND channel = 'GYRO_K'");
    EXPECT_GT(dropped, 0);
    EXPECT_EQ(stored + dropped + gaps, published);
    EXPECT_LE(stored, 100 + 1000 + 10);
    std::cout << "published " << published << ", stored " << stored << ", dropped " << dropped
              << ", seq gaps " << gaps << "\n";
}

TEST_F(Fault, DiskFullHoldsRowsAndWritesThemWhenSpaceIsFreed) {
    ScratchMount m;
    if (const std::string why = m.MountTmpfs("full", 4096); !why.empty()) {
        GTEST_SKIP() << why;
    }
    StartAndStore(m.dir() + "/gyrocal.db", 7852);
    // Fill the file system to the last byte (dd stops with "No space left on device").
    const std::string filler = m.dir() + "/filler";
    ScratchMount::Run("dd if=/dev/zero of=" + filler + " bs=4k");
    for (int round = 0; round < 40 && status_.state != "db_blocked:disk_full"; ++round) {
        Publish(500);  // until the WAL cannot grow
        WaitStatus([&] { return status_.state == "db_blocked:disk_full"; }, 1s);
    }
    ASSERT_EQ(status_.state, "db_blocked:disk_full");
    Publish(1000);
    EXPECT_LT(Stored(), seq_);
    fs::remove(filler);
    ExpectRecoveredThenStop("disk full");
}

TEST_F(Fault, ReadOnlyDatabaseFileHoldsRowsAndWritesThemWhenWritableAgain) {
    ScratchMount m;
    if (const std::string why = m.MountExt4("readonly", 16); !why.empty()) {
        GTEST_SKIP() << why;
    }
    StartAndStore(m.dir() + "/gyrocal.db", 7853);
    // The database and its WAL refuse writes (EPERM), as a read-only file would; -shm is left
    // alone (SQLite maps it).
    const std::string files = db_ + " " + db_ + "-wal";
    ASSERT_EQ(ScratchMount::Run("chattr +i " + files), "");
    Publish(1000);
    const bool blocked = WaitStatus([&] { return status_.state == "db_blocked:read-only"; });
    ScratchMount::Run("chattr -i " + files);  // before any assertion can end the test
    ASSERT_TRUE(blocked) << "state " << status_.state;
    Publish(200);
    ExpectRecoveredThenStop("read-only");
}

TEST(FaultAtStart, ADatabaseOnAReadOnlyFileSystemIsAClearErrorAndExitTwo) {
    ScratchMount m;
    if (const std::string why = m.MountTmpfs("rostart", 4096); !why.empty()) {
        GTEST_SKIP() << why;
    }
    const std::string db = m.dir() + "/gyrocal.db";
    { db::StoreWriter w(db, {}); }  // a valid gyrocal database, then the mount goes read-only
    ASSERT_EQ(ScratchMount::Run("mount -o remount,ro " + m.dir()), "");
    const std::string err_path = FreshDbPath("fault_rostart.err");  // not on the read-only mount
    launch::ChildProcess rec({std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db", db,
                              "--lcm-url", UrlForPort(7854)},
                             "", err_path);
    const auto st = rec.Wait(10s);
    ASSERT_TRUE(st.has_value());
    EXPECT_EQ(st->code, 2) << st->Describe();
    const std::string err = launch::ReadLog(err_path);
    EXPECT_NE(err.find("--db"), std::string::npos) << err;
    EXPECT_NE(err.find(db), std::string::npos) << err;
    EXPECT_NE(err.find("Read-only file system"), std::string::npos) << err;
}

}  // namespace
}  // namespace gyrocal::testing
