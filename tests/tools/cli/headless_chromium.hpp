#pragma once
// A real browser for tests: Debian's chromium, headless, driven over the DevTools protocol on a
// pipe (--remote-debugging-pipe: the browser reads commands on fd 3 and writes replies and events
// on fd 4, one JSON message per NUL-terminated chunk). No network port, no extra package, no
// script runtime: the test talks to the browser directly.
//
// Flags: headless, no sandbox (containers), no GPU, no QUIC, no first-run UI, no background
// networking, component updates or sync (nothing leaves the machine), a fresh --user-data-dir.
// Every event the browser sends is kept (console messages, exceptions, log entries, network
// requests) for the test to inspect. Waits are bounded; a call that gets no reply in time throws.
#include <sys/types.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"

namespace gyrocal::testing {

class HeadlessChromium {
public:
    // "chromium" (or "chromium-browser") found on PATH; "" when neither is installed.
    static std::string Find();

    // Starts the browser; its own output goes to `log_path`. Throws std::runtime_error.
    HeadlessChromium(const std::string& executable, const std::string& user_data_dir,
                     const std::string& log_path);
    ~HeadlessChromium();
    HeadlessChromium(const HeadlessChromium&) = delete;
    HeadlessChromium& operator=(const HeadlessChromium&) = delete;

    // Sends a command (to the browser, or to a page's session) and returns its "result".
    // Throws std::runtime_error on a protocol error or when no reply comes within `timeout`.
    nlohmann::json Call(const std::string& method,
                        const nlohmann::json& params = nlohmann::json::object(),
                        const std::string& session = "",
                        std::chrono::milliseconds timeout = std::chrono::seconds(60));

    // Opens `url` in a new page of `width_px` with Page, Runtime, Log and Network events on, and
    // returns the page's session once its load event fired (within `timeout`).
    std::string Open(const std::string& url, int width_px, std::chrono::milliseconds timeout);

    // Evaluates a JavaScript expression in the page and returns its value (by value).
    nlohmann::json Evaluate(const std::string& session, const std::string& expression);

    // A PNG of the whole page (beyond the viewport), as bytes.
    std::string Screenshot(const std::string& session);

    // Every event received so far (method, params), in arrival order.
    const std::vector<nlohmann::json>& events() const { return events_; }

private:
    nlohmann::json Read(std::chrono::steady_clock::time_point deadline);  // next message

    std::unique_ptr<launch::ChildProcess> child_;  // its own process group, dies with the test
    int to_browser_ = -1, from_browser_ = -1;
    std::string buffer_;
    int next_id_ = 0;
    std::vector<nlohmann::json> events_;
};

// Standard base64 (RFC 4648) to bytes; throws std::runtime_error on a bad character.
std::string DecodeBase64(const std::string& text);

}  // namespace gyrocal::testing
