// SHA-256 of an input file against the published test vectors (FIPS 180-2, appendix B).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "producers/csv/file_digest.hpp"

namespace gyrocal::csv {
namespace {

std::string DigestOf(const std::string& content) {
    const auto path =
        std::filesystem::temp_directory_path() / ("gyrocal_digest_" + std::to_string(::getpid()));
    std::ofstream(path, std::ios::binary) << content;
    const std::string hex = Sha256HexOfFile(path.string());
    std::filesystem::remove(path);
    return hex;
}

TEST(FileDigest, MatchesTheStandardTestVectors) {
    EXPECT_EQ(DigestOf("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(DigestOf(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    // One million 'a': several read buffers.
    EXPECT_EQ(DigestOf(std::string(1000000, 'a')),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(FileDigest, AnUnreadableFileIsNamed) {
    try {
        Sha256HexOfFile("/nonexistent/run7.csv");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/run7.csv: cannot be read"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace gyrocal::csv
