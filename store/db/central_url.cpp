#include "store/db/central_url.hpp"

#include <cctype>
#include <vector>

namespace gyrocal::db {
namespace {

constexpr const char* kMask = "***";

bool StartsWith(const std::string& s, size_t at, const std::string& prefix) {
    return s.compare(at, prefix.size(), prefix) == 0;
}

// Length of the scheme prefix ("postgresql://" or "postgres://") at `at`, 0 when none.
size_t SchemeAt(const std::string& s, size_t at) {
    for (const char* p : {"postgresql://", "postgres://"}) {
        if (StartsWith(s, at, p)) return std::string(p).size();
    }
    return 0;
}

std::string PercentDecoded(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() &&
            std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
            out += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// The passwords a URL carries: the userinfo's and each *password=VALUE parameter's.
std::vector<std::string> Passwords(const std::string& url) {
    std::vector<std::string> out;
    const size_t scheme = SchemeAt(url, 0);
    if (scheme == 0) return out;
    const size_t authority_end = url.find_first_of("/?", scheme);
    const std::string authority = url.substr(scheme, authority_end - scheme);
    if (const size_t at = authority.rfind('@'); at != std::string::npos) {
        const std::string userinfo = authority.substr(0, at);
        if (const size_t colon = userinfo.find(':'); colon != std::string::npos)
            out.push_back(userinfo.substr(colon + 1));
    }
    if (const size_t q = url.find('?'); q != std::string::npos) {
        size_t i = q + 1;
        while (i < url.size()) {
            const size_t amp = std::min(url.find('&', i), url.size());
            const std::string kv = url.substr(i, amp - i);
            const size_t eq = kv.find('=');
            if (eq != std::string::npos && kv.substr(0, eq).find("password") != std::string::npos)
                out.push_back(kv.substr(eq + 1));
            i = amp + 1;
        }
    }
    return out;
}

// Passwords shorter than this are not searched for in messages: masking every "y" of a message
// would make it unreadable, and such a password is not one (the URL itself is always masked).
constexpr size_t kShortestRedacted = 4;

void ReplaceAll(std::string& text, const std::string& what) {
    if (what.size() < kShortestRedacted) return;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at)) {
        text.replace(at, what.size(), kMask);
        at += std::string(kMask).size();
    }
}

}  // namespace

bool IsCentralUrl(const std::string& s) { return SchemeAt(s, 0) != 0; }

std::string WithoutCredentials(const std::string& s) {
    const size_t scheme = SchemeAt(s, 0);
    if (scheme == 0) return s;
    std::string out = s;
    const size_t authority_end = std::min(out.find_first_of("/?", scheme), out.size());
    const size_t at = out.rfind('@', authority_end);
    if (at != std::string::npos && at >= scheme) {
        const size_t colon = out.find(':', scheme);
        if (colon != std::string::npos && colon < at) out.replace(colon + 1, at - colon - 1, kMask);
    }
    if (const size_t q = out.find('?'); q != std::string::npos) {
        size_t i = q + 1;
        while (i < out.size()) {
            const size_t amp = std::min(out.find('&', i), out.size());
            const size_t eq = out.find('=', i);
            if (eq < amp && out.substr(i, eq - i).find("password") != std::string::npos) {
                out.replace(eq + 1, amp - eq - 1, kMask);
                i = eq + 1 + std::string(kMask).size() + 1;
            } else {
                i = amp + 1;
            }
        }
    }
    return out;
}

std::string RedactCredentials(const std::string& text, const std::string& url) {
    std::string out = text;
    for (const std::string& p : Passwords(url)) {
        ReplaceAll(out, p);
        ReplaceAll(out, PercentDecoded(p));
    }
    return out;
}

std::string WithoutCredentialsIn(const std::string& text) {
    std::string out;
    size_t i = 0;
    while (i < text.size()) {
        if (SchemeAt(text, i) == 0) {
            out += text[i++];
            continue;
        }
        // A URL ends at white space or a quote (command lines, JSON strings).
        size_t end = i;
        while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end])) &&
               text[end] != '"' && text[end] != '\'')
            ++end;
        out += WithoutCredentials(text.substr(i, end - i));
        i = end;
    }
    return out;
}

}  // namespace gyrocal::db
