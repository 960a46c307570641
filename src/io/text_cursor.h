// What the file readers share: a cursor over a text buffer that counts lines, errors that name
// their line, OBJ index resolution, and reading a whole file into memory.
#pragma once

#include "qex/io.h"

#include "io/checked_int.h"

#include <fast_float/fast_float.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>

namespace qex::io_detail {

/// A position in a text buffer and the 1-based line it is on.
struct Cursor {
    const char* p;
    const char* end;
    std::int64_t line = 1;

    /// Skips spaces, tabs and carriage returns (not line ends).
    void skip_blanks() {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    }
    /// Skips blanks; whether the record ends here (buffer end, line end or comment).
    bool at_eol() {
        skip_blanks();
        return p >= end || *p == '\n' || *p == '#';
    }
    /// Moves past the next line end (to the buffer end if there is none) and counts a line.
    void skip_line() {
        const void* nl = p < end ? std::memchr(p, '\n', static_cast<std::size_t>(end - p)) : nullptr;
        p = nl ? static_cast<const char*>(nl) + 1 : end;
        ++line;
    }
    /// The word at the cursor (up to a blank or line end), moving past it.
    std::string_view read_key() {
        const char* kw = p;
        while (p < end && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r') ++p;
        return std::string_view(kw, static_cast<std::size_t>(p - kw));
    }
    /// A number after optional blanks, which must end at a blank, line end or comment. On
    /// failure the cursor stays after the blanks when no number was read there, and moves past
    /// the number when one was read but something else follows it.
    bool read_double(double& x) {
        skip_blanks();
        const char* start = p;
        if (p < end && *p == '+') ++p; // fast_float does not take a leading '+'
        auto r = fast_float::from_chars(p, end, x);
        if (r.ec != std::errc() || r.ptr == p) {
            p = start;
            return false;
        }
        p = r.ptr;
        return p >= end || *p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '#';
    }
    /// A signed decimal integer right at the cursor. Fails, leaving the cursor where it was, if
    /// there is no digit or the value passes 2^40 before its last digit (so it never overflows).
    bool read_int(std::int64_t& x) {
        const char* start = p;
        bool neg = false;
        if (p < end && (*p == '-' || *p == '+')) neg = *p++ == '-';
        std::int64_t v = 0;
        const char* digits = p;
        while (p < end && *p >= '0' && *p <= '9') {
            if (v > (std::int64_t{1} << 40)) {
                p = start;
                return false;
            }
            v = v * 10 + (*p++ - '0');
        }
        if (p == digits) {
            p = start;
            return false;
        }
        x = neg ? -v : v;
        return true;
    }
    /// The signed decimal integer written at the cursor, as text ("" if there is none): to name
    /// one that read_int() refused as too long, out of range rather than malformed.
    std::string too_long_integer() const {
        const char* q = p < end && (*p == '-' || *p == '+') ? p + 1 : p;
        const char* const digits = q;
        while (q < end && *q >= '0' && *q <= '9') ++q;
        if (q == digits) return "";
        const auto n = static_cast<std::size_t>(q - p);
        return n <= 24 ? std::string(p, n) : std::string(p, 20) + "... (" + std::to_string(q - digits) + " digits)";
    }
};

/// An error of kind `c` on `line`, its message prefixed by "line N: ".
inline IoError err(IoError::Code c, std::int64_t line, const std::string& msg) {
    return {c, "line " + std::to_string(line) + ": " + msg, line};
}

/// Resolves a 1-based (or negative, relative) OBJ index against `count` elements; false if it
/// names none, or one beyond what an int holds.
inline bool resolve(std::int64_t idx, std::size_t count, int& out) {
    std::int64_t n = 0;
    if (!checked_int(count, n) || idx == INT64_MIN) return false;
    if (idx > 0 && idx <= n) return checked_int(idx - 1, out);
    if (idx < 0 && -idx <= n) return checked_int(n + idx, out);
    return false;
}

/// Reads the whole file at `path` into `data`; false if it cannot be opened or read.
inline bool read_file(const std::string& path, std::string& data) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    data.clear();
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
    const bool ok = std::ferror(f) == 0;
    std::fclose(f);
    return ok;
}

} // namespace qex::io_detail
