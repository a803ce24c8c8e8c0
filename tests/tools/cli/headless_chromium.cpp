#include "tests/tools/cli/headless_chromium.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "lcmtypes/launch/child_process.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"

namespace gyrocal::testing {

std::string HeadlessChromium::Find() {
    for (const char* name : {"chromium", "chromium-browser"})
        if (std::string p = plot::gnuplot::FindOnPath(name); !p.empty()) return p;
    return "";
}

HeadlessChromium::HeadlessChromium(const std::string& exe, const std::string& user_data_dir,
                                   const std::string& log_path) {
    int to[2], from[2];
    if (::pipe(to) != 0 || ::pipe(from) != 0) throw std::runtime_error("pipe() failed");
    std::vector<std::string> args = {exe,
                                     "--headless",
                                     "--no-sandbox",
                                     "--disable-gpu",
                                     "--disable-quic",
                                     "--no-first-run",
                                     "--disable-background-networking",
                                     "--disable-component-update",
                                     "--disable-sync",
                                     "--hide-scrollbars",
                                     "--remote-debugging-pipe",
                                     "--user-data-dir=" + user_data_dir,
                                     "about:blank"};
    // fd 3: what the browser reads; fd 4: what it writes.
    const launch::ChildOptions options{log_path, log_path, "", {to[0], from[1]}};
    try {
        child_ = std::make_unique<launch::ChildProcess>(args, options);
    } catch (...) {
        for (int fd : {to[0], to[1], from[0], from[1]}) ::close(fd);
        throw;
    }
    ::close(to[0]);
    ::close(from[1]);
    to_browser_ = to[1];
    from_browser_ = from[0];
    ::signal(SIGPIPE, SIG_IGN);  // a browser that died makes write() fail, not the test
}

HeadlessChromium::~HeadlessChromium() {
    try {
        if (child_) Call("Browser.close", nlohmann::json::object(), "", std::chrono::seconds(10));
    } catch (...) {
    }
    if (to_browser_ >= 0) ::close(to_browser_);
    if (from_browser_ >= 0) ::close(from_browser_);
    if (child_ && !child_->Wait(std::chrono::seconds(10))) {  // up to 10 s to exit by itself
        child_->Signal(SIGKILL);
        child_->Wait();
    }
}

nlohmann::json HeadlessChromium::Read(std::chrono::steady_clock::time_point deadline) {
    while (true) {
        const size_t nul = buffer_.find('\0');
        if (nul != std::string::npos) {
            const std::string msg = buffer_.substr(0, nul);
            buffer_.erase(0, nul + 1);
            return nlohmann::json::parse(msg);
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) throw std::runtime_error("no message from chromium in time");
        pollfd p{from_browser_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
        char chunk[65536];
        const ssize_t n = ::read(from_browser_, chunk, sizeof chunk);
        if (n <= 0) throw std::runtime_error("chromium closed its DevTools pipe (see its log)");
        buffer_.append(chunk, static_cast<size_t>(n));
    }
}

nlohmann::json HeadlessChromium::Call(const std::string& method, const nlohmann::json& params,
                                      const std::string& session,
                                      std::chrono::milliseconds timeout) {
    const int id = ++next_id_;
    nlohmann::json cmd = {{"id", id}, {"method", method}, {"params", params}};
    if (!session.empty()) cmd["sessionId"] = session;
    const std::string text = cmd.dump() + std::string(1, '\0');
    for (size_t off = 0; off < text.size();) {
        const ssize_t n = ::write(to_browser_, text.data() + off, text.size() - off);
        if (n <= 0) throw std::runtime_error("cannot write to chromium's DevTools pipe");
        off += static_cast<size_t>(n);
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
        nlohmann::json m = Read(deadline);
        if (!m.contains("id")) {
            events_.push_back(std::move(m));
            continue;
        }
        if (m["id"] != id) continue;
        if (m.contains("error")) throw std::runtime_error(method + ": " + m["error"].dump());
        return m.value("result", nlohmann::json::object());
    }
}

std::string HeadlessChromium::Open(const std::string& url, int width_px,
                                   std::chrono::milliseconds timeout) {
    const std::string target = Call("Target.createTarget", {{"url", "about:blank"}})["targetId"];
    const std::string s =
        Call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}})["sessionId"];
    for (const char* domain : {"Page.enable", "Runtime.enable", "Log.enable", "Network.enable"})
        Call(domain, {}, s);
    Call("Emulation.setDeviceMetricsOverride",
         {{"width", width_px}, {"height", 900}, {"deviceScaleFactor", 1}, {"mobile", false}}, s);
    const size_t before = events_.size();
    Call("Page.navigate", {{"url", url}}, s);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (size_t i = before;; ++i) {
        while (i >= events_.size()) events_.push_back(Read(deadline));
        const nlohmann::json& e = events_[i];
        if (e.value("method", "") == "Page.loadEventFired" && e.value("sessionId", "") == s)
            return s;
    }
}

nlohmann::json HeadlessChromium::Evaluate(const std::string& session,
                                          const std::string& expression) {
    const nlohmann::json r =
        Call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}}, session);
    if (r.contains("exceptionDetails"))
        throw std::runtime_error("script failed: " + r["exceptionDetails"].dump());
    return r["result"].value("value", nlohmann::json());
}

std::string HeadlessChromium::Screenshot(const std::string& session) {
    const nlohmann::json m = Call("Page.getLayoutMetrics", {}, session);
    const double width = m["cssContentSize"]["width"], height = m["cssContentSize"]["height"];
    const nlohmann::json r =
        Call("Page.captureScreenshot",
             {{"format", "png"},
              {"captureBeyondViewport", true},
              {"clip", {{"x", 0}, {"y", 0}, {"width", width}, {"height", height}, {"scale", 1}}}},
             session);
    return DecodeBase64(r["data"]);
}

std::string DecodeBase64(const std::string& text) {
    std::string out;
    unsigned value = 0;
    int bits = 0;
    for (char c : text) {
        int v;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+')
            v = 62;
        else if (c == '/')
            v = 63;
        else if (c == '=' || c == '\n' || c == '\r')
            continue;
        else
            throw std::runtime_error(std::string("not base64: '") + c + "'");
        value = (value << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((value >> bits) & 0xff);
        }
    }
    return out;
}

}  // namespace gyrocal::testing
