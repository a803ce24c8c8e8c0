#include "producers/line_source/line_input.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace gyrocal::line_source {

LineInput::LineInput(int fd, std::string name) : fd_(fd), name_(std::move(name)) {
    if (isatty(fd_)) {
        termios t{};
        if (tcgetattr(fd_, &t) == 0) {
            saved_tty_ = t;
            cfmakeraw(&t);
            tcsetattr(fd_, TCSANOW, &t);
        }
    }
}

LineInput::~LineInput() {
    if (saved_tty_) tcsetattr(fd_, TCSANOW, &*saved_tty_);
    if (fd_ > 0) close(fd_);
}

bool LineInput::Read(int timeout_ms, std::vector<InputLine>* lines) {
    pollfd p{fd_, POLLIN, 0};
    const int r = poll(&p, 1, timeout_ms);
    if (r < 0) {
        if (errno == EINTR) return true;
        throw std::runtime_error(name_ + ": poll failed: " + std::strerror(errno));
    }
    if (r == 0) return true;
    char buf[65536];
    const ssize_t n = read(fd_, buf, sizeof buf);
    if (n < 0) {
        if (errno == EINTR || errno == EAGAIN) return true;
        throw std::runtime_error(name_ + ": read failed: " + std::strerror(errno));
    }
    if (n == 0) {  // end of input: the last line may lack its newline
        if (!pending_.empty() || discarding_) lines->push_back({std::move(pending_), discarding_});
        pending_.clear();
        return false;
    }
    for (ssize_t i = 0; i < n; ++i) {
        const char c = buf[i];
        if (c == '\n') {
            lines->push_back({std::move(pending_), discarding_});
            pending_.clear();
            discarding_ = false;
        } else if (!discarding_) {
            pending_ += c;
            if (pending_.size() > kMaxLineBytes) {  // junk on the line: drop up to the newline
                pending_.clear();
                discarding_ = true;
            }
        }
    }
    return true;
}

}  // namespace gyrocal::line_source
