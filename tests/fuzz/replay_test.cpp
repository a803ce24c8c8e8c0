// Every committed input of every fuzz harness, replayed through the harness as a normal test:
// the seed corpora (tests/fuzz/corpus/<harness>/) and the inputs that once broke a contract
// (tests/fuzz/regressions/<harness>/, each fixed since). So CI runs them with the ordinary
// build, no clang needed. A broken contract aborts (FUZZ_CHECK) after the file's name is printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#define GYROCAL_FUZZ_HARNESS(name) \
    extern "C" int GyrocalFuzz_##name(const uint8_t* data, size_t size);
#include "fuzz_harnesses.inc"
#undef GYROCAL_FUZZ_HARNESS

namespace {

namespace fs = std::filesystem;
using Entry = int (*)(const uint8_t*, size_t);

struct Harness {
    std::string name;
    Entry entry;
};

const std::vector<Harness>& Harnesses() {
#define GYROCAL_FUZZ_HARNESS(name) {#name, &GyrocalFuzz_##name},
    static const std::vector<Harness> all = {
#include "fuzz_harnesses.inc"
    };
#undef GYROCAL_FUZZ_HARNESS
    return all;
}

std::vector<uint8_t> ReadAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Replays every file under `dir`; returns how many.
int ReplayDir(const Harness& h, const fs::path& dir) {
    if (!fs::exists(dir)) return 0;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.is_regular_file()) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        std::cerr << "replaying " << h.name << " " << f.string() << "\n";
        const std::vector<uint8_t> bytes = ReadAll(f);
        EXPECT_EQ(h.entry(bytes.data(), bytes.size()), 0) << f;
    }
    return static_cast<int>(files.size());
}

class FuzzReplay : public ::testing::TestWithParam<Harness> {};

TEST_P(FuzzReplay, SeedsAndRegressionsKeepTheContract) {
    const Harness& h = GetParam();
    const fs::path root(GYROCAL_FUZZ_DIR);
    const int seeds = ReplayDir(h, root / "corpus" / h.name);
    ReplayDir(h, root / "regressions" / h.name);
    // A harness without seeds would start from nothing and find little in a short run.
    EXPECT_GT(seeds, 0) << "no seed corpus in " << (root / "corpus" / h.name);
}

INSTANTIATE_TEST_SUITE_P(Harnesses, FuzzReplay, ::testing::ValuesIn(Harnesses()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
