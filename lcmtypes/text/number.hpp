#pragma once
// Numbers as text: the one helper every layer uses for messages, tables, reports and help texts.
// Two forms: significant digits (printf's "%.*g": 0.00123, 1.5e+06; what std::ostream writes
// with that precision) and one printf conversion chosen by the caller ("%.4f", "%+.2e"). The
// *OrDash forms write "-" for NaN and infinities, for tables where a missing figure should look
// missing; the plain forms write what printf writes ("nan", "inf").
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

namespace gyrocal::text {

// v with `digits` significant digits ("%.*g").
inline std::string Sig(double v, int digits = 6) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

// printf of `format` with its arguments (numbers, C strings), never truncated. A C variadic
// with printf's format attribute, so the compiler checks every call's arguments against its
// format as it does printf's.
[[gnu::format(printf, 1, 2)]] inline std::string Printf(const char* format, ...) {
    std::va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    char buf[128];
    const int n = std::vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    std::string out;
    if (n >= 0 && static_cast<size_t>(n) < sizeof buf) {
        out.assign(buf, static_cast<size_t>(n));
    } else if (n >= 0) {
        out.resize(static_cast<size_t>(n) + 1);
        std::vsnprintf(out.data(), out.size(), format, again);
        out.resize(static_cast<size_t>(n));
    }
    va_end(again);
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
