// Fuzz opening a file that is said to be a gyrocal database: the bytes written to a file, then
// the readers' path (db::OpenForQuery, which migrates an older gyrocal file; ListRuns,
// ShowRun and SensorHistory, as `gyrocal runs/show/history` call them) and the recorder's
// (StoreWriter: open, migrate, OpenRunId, LastSeqs, one batch written).
// Contract: every failure is a db::StoreError, which the commands print as one line and exit
// non-zero on; nothing else is thrown and nothing crashes.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "store/db/query.hpp"
#include "store/db/writer.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace gyrocal::db;

std::string FuzzPath() {
    namespace fs = std::filesystem;
    const fs::path dir = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    return (dir / ("gyrocal_fuzz_store_" + std::to_string(::getpid()) + ".db")).string();
}

void WriteFile(const std::string& path, const uint8_t* data, size_t size) {
    for (const char* ext : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(path + ext);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

void Read(const std::string& path) {
    try {
        auto db = OpenForQuery(path);
        const auto runs = ListRuns(*db, RunFilter{});
        for (size_t i = 0; i < runs.size() && i < 3; ++i) {
            const RunDetail d = ShowRun(*db, runs[i].run_id);
            for (const auto& id : d.run.sensor_ids) {
                if (SensorExists(*db, id)) SensorHistory(*db, id, true);
            }
        }
    } catch (const StoreError&) {
    }
}

void Record(const std::string& path) {
    try {
        StoreWriter w(path, WriterInfo{"fuzz", "fuzzhost", 1});
        const std::string run = w.OpenRunId();
        w.LastSeqs(run);
        GyroRow g;
        g.run_id = run;
        g.sensor_id = "S01";
        g.utime = 1;
        RunEventRow e;
        e.run_id = "F1";
        e.event = "start";
        e.sensor_ids = {"S01"};
        w.Write({g, e}, {{{run, "GYRO_S01"}, LossDelta{1, 0, 0, 0}}});
    } catch (const StoreError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = FuzzPath();
    WriteFile(path, data, size);
    Read(path);
    WriteFile(path, data, size);
    Record(path);
    return 0;
}
