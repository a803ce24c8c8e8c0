#pragma once
// Numbers as text: the one helper every layer uses for messages, tables, reports and help texts.
// Two forms: significant digits (printf's "%.*g": 0.00123, 1.5e+06; what std::ostream writes
// with that precision) and one printf conversion chosen by the caller ("%.4f", "%+.2e"). The
// *OrDash forms write "-" for NaN and infinities, for tables where a missing figure should look
// missing; the plain forms write what printf writes ("nan", "inf").
#include <cmath>
#include <cstdio>
#include <string>

namespace gyrocal::text {

// v with `digits` significant digits ("%.*g").
inline std::string Sig(double v, int digits = 6) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

// printf of `format` with `args` (numbers), never truncated.
template <class... Args>
std::string Printf(const char* format, Args... args) {
    char buf[128];
    const int n = std::snprintf(buf, sizeof buf, format, args...);
    if (n < 0) return "";
    if (static_cast<size_t>(n) < sizeof buf) return std::string(buf, static_cast<size_t>(n));
    std::string out(static_cast<size_t>(n) + 1, '\0');
    std::snprintf(out.data(), out.size(), format, args...);
    out.resize(static_cast<size_t>(n));
    return out;
}

// "-" when v is not finite, else Sig(v, digits).
inline std::string SigOrDash(double v, int digits = 6) {
    return std::isfinite(v) ? Sig(v, digits) : "-";
}

// "-" when v is not finite, else Printf(format, v).
inline std::string PrintfOrDash(const char* format, double v) {
    return std::isfinite(v) ? Printf(format, v) : "-";
}

}  // namespace gyrocal::text
