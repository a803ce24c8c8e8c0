// Fuzz gyrocal-line-source's input side: bytes through LineInput (read from a file descriptor,
// split at newlines) and LineStream (header, rows, repeated headers, bad lines).
// Contract: nothing throws; the lines joined with newlines give back the input (no line here is
// over LineInput::kMaxLineBytes: libFuzzer's -max_len is smaller); after a fatal line (no valid
// header) every line is fatal; every row is one the format allows (fuzz::CheckRow).
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "producers/line_source/line_input.hpp"
#include "producers/line_source/line_stream.hpp"
#include "tests/fuzz/fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gyrocal;
    const int fd = memfd_create("gyrocal_fuzz_line_stream", MFD_CLOEXEC);
    FUZZ_CHECK(fd > 0, "memfd_create failed");
    FUZZ_CHECK(write(fd, data, size) == static_cast<ssize_t>(size), "memfd write failed");
    lseek(fd, 0, SEEK_SET);
    std::vector<line_source::InputLine> lines;
    {
        line_source::LineInput input(fd, "fuzz-stream");  // owns and closes fd
        while (input.Read(0, &lines)) {
        }
    }
    std::string joined;
    for (size_t i = 0; i < lines.size(); ++i) {
        FUZZ_CHECK(!lines[i].overlong, "a short line was flagged overlong");
        joined += lines[i].text;
        if (i + 1 < lines.size() || (size > 0 && data[size - 1] == '\n')) joined += '\n';
    }
    FUZZ_CHECK(joined == std::string(reinterpret_cast<const char*>(data), size),
               "the lines do not give back the input");

    line_source::LineStream stream("fuzz-stream", sensor::TempTransfer{});
    std::map<std::string, long long> last_us;
    bool fatal = false;
    for (const line_source::InputLine& line : lines) {
        const line_source::LineOutcome o = stream.Feed(line);
        FUZZ_CHECK(!fatal || o.kind == line_source::LineOutcome::Kind::kFatal,
                   "a line was read after a fatal one");
        fatal = o.kind == line_source::LineOutcome::Kind::kFatal;
        FUZZ_CHECK(o.row.has_value() == (o.kind == line_source::LineOutcome::Kind::kRow),
                   "row without kRow");
        if (o.row) fuzz::CheckRow(*o.row, last_us);
        if (o.kind == line_source::LineOutcome::Kind::kBad || fatal) {
            FUZZ_CHECK(!o.message.empty(), "a bad line without a reason");
        }
    }
    return 0;
}
