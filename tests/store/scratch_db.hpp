#pragma once
// Scratch SQLite files for the store's and the recorder's tests, and single numbers read from them
// (also while another process is still writing them).
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>

#include "store/db/schema.hpp"
#include "store/db/sqlite_db.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::testing {

// A path for a test database in the temp folder, unique to this process (CTest runs each test in
// a process of its own), with no file, -wal or -shm left from an earlier run.
inline std::string FreshDbPath(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "gyrocal_store_tests";
    std::filesystem::create_directories(dir);
    const std::string p = (dir / (name + "_" + std::to_string(::getpid()))).string();
    for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(p + ext);
    return p;
}

// The first column of the first row of `sql`, -1 when there is no row.
inline int64_t Count(db::Db& db, const std::string& sql) {
    db::Stmt s(db, sql);
    return s.Step() ? s.Int(0) : -1;
}

// The same on a read-only connection of its own to the file at `db_path`.
inline int64_t Count(const std::string& db_path, const std::string& sql) {
    db::Db db(db_path, db::Db::Mode::kReadOnly);
    return Count(db, sql);
}

// Polls `sql` until it returns `expected` or `timeout` passes; returns the last value.
inline int64_t WaitForCount(const std::string& db_path, const std::string& sql, int64_t expected,
                            std::chrono::milliseconds timeout) {
    int64_t n = -1;
    WaitUntil(
        [&] {
            try {
                n = Count(db_path, sql);
            } catch (const std::exception&) {
                n = -1;  // not created yet
            }
            return n == expected;
        },
        timeout, std::chrono::milliseconds(50));
    return n;
}

// A new database at schema `version`, as an older gyrocal left it, for a test to fill.
struct OldDatabase : db::Db {
    OldDatabase(const std::string& path, int version) : db::Db(path, Mode::kReadWriteCreate) {
        db::ConfigureConnection(*this);
        db::Migrate(*this, version);
    }
};

}  // namespace gyrocal::testing
