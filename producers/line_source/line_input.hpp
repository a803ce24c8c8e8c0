#pragma once
// Reading lines from a file descriptor without blocking the process loop: poll() with a short
// timeout, read what is there, hand out complete lines. A tty is put in raw mode (no echo, no
// line editing, no CR/LF translation; baud rate and framing are left as configured, e.g. by
// stty) so that bytes arrive as the device sends them.
#include <termios.h>

#include <optional>
#include <string>
#include <vector>

namespace gyrocal::line_source {

struct InputLine {
    std::string text;       // without the newline
    bool overlong = false;  // longer than LineInput::kMaxLineBytes: text dropped, line counted
};

class LineInput {
public:
    static constexpr size_t kMaxLineBytes = 65536;

    // fd is owned (closed) unless it is 0 (stdin). A tty is switched to raw mode and restored.
    LineInput(int fd, std::string name);
    LineInput(const LineInput&) = delete;
    LineInput& operator=(const LineInput&) = delete;
    ~LineInput();

    // Waits up to timeout_ms for data and appends complete lines to `lines`.
    // Returns false at end of input (after the last partial line is delivered).
    // Throws std::runtime_error on a read error.
    bool Read(int timeout_ms, std::vector<InputLine>* lines);
    const std::string& name() const { return name_; }

private:
    int fd_;
    std::string name_;
    std::string pending_;
    bool discarding_ = false;
    std::optional<termios> saved_tty_;
};

}  // namespace gyrocal::line_source
