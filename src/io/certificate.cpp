// qex extract's certificate (qex::Certificate) as a file: an OBJ map (the given positions and
// triangles, the repaired map's UVs per corner, every digit) after a header of comments that
// the reader checks strictly: the format and its version, the grid scale, and the repaired
// triangles. Any OBJ reader reads the map; `qex check --certificate` reads it all.
//
//   # qex certificate 1
//   # grid_scale 1
//   # repaired 5
//   # r 12 13 14 20 21
//   v x y z ...    vt u v ... (3 per triangle, in order)    f a/ta b/tb c/tc ...
#include "file_io.h"
#include "qex/io.h"
#include "qex/verify.h"

#include <algorithm>
#include <charconv>
#include <cinttypes>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>

namespace qex {
namespace {

constexpr const char* kMagic = "# qex certificate 1";
constexpr std::size_t kPerLine = 16; // repaired triangles per `# r` line

/// A non-negative decimal integer of at most `most`, digits only, the whole of `s`.
bool whole_number(std::string_view s, std::int64_t most, std::int64_t& out) {
    if (s.empty() || s.size() > 19) return false;
    for (char ch : s)
        if (ch < '0' || ch > '9') return false;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size() && out <= most;
}

/// Reads the header lines of `text` into `c` (grid scale, repaired list): exactly as many
/// repaired triangles as announced, in `# r` lines of at least one each, and no `# r` line after.
IoError parse_header(std::string_view text, Certificate& c) {
    std::int64_t line = 0, count = -1;
    std::size_t at = 0;
    const auto fail = [&](const std::string& what) {
        return IoError{IoError::Code::Syntax, "certificate line " + std::to_string(line) + ": " + what, line};
    };
    while (count < 0 || static_cast<std::int64_t>(c.repaired.size()) < count) {
        if (at >= text.size()) return ++line, fail("the header ends early");
        const std::size_t eol = std::min(text.find('\n', at), text.size());
        std::string_view s = text.substr(at, eol - at);
        if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
        at = eol + 1;
        ++line;
        std::int64_t n = 0;
        if (line == 1) {
            if (s != kMagic) return fail(std::string("not a qex certificate (expected '") + kMagic + "')");
        } else if (line == 2) {
            if (s.rfind("# grid_scale ", 0) != 0 || !whole_number(s.substr(13), std::int64_t{1} << 20, n) || n < 1)
                return fail("expected '# grid_scale K' with K a whole number from 1 to 2^20");
            c.grid_scale = static_cast<int>(n);
        } else if (line == 3) {
            if (s.rfind("# repaired ", 0) != 0 || !whole_number(s.substr(11), INT32_MAX, count))
                return fail("expected '# repaired N' with N a whole number below 2^31");
        } else {
            if (s.rfind("# r ", 0) != 0 || s.size() == 4) return fail("expected '# r' and repaired triangles");
            s.remove_prefix(4);
            while (!s.empty()) {
                const std::size_t sp = std::min(s.find(' '), s.size());
                if (!whole_number(s.substr(0, sp), INT32_MAX, n))
                    return fail("a repaired triangle must be a whole number below 2^31");
                if (static_cast<std::int64_t>(c.repaired.size()) >= count)
                    return fail("more repaired triangles than the " + std::to_string(count) + " announced");
                c.repaired.push_back(static_cast<std::int32_t>(n));
                s.remove_prefix(std::min(sp + 1, s.size()));
            }
        }
    }
    if (text.substr(std::min(at, text.size())).rfind("# r ", 0) == 0)
        return ++line, fail("more repaired triangles than the " + std::to_string(count) + " announced");
    return {};
}

} // namespace

IoError parse_certificate(const char* data, std::size_t size, Certificate& out) {
    out = Certificate{};
    const std::string_view text(data, size);
    if (IoError e = parse_header(text, out); !e.ok()) {
        out = Certificate{};
        return e;
    }
    if (IoError e = parse_obj(data, size, out.map, 1); !e.ok()) {
        out = Certificate{};
        e.message = "certificate: " + e.message;
        return e;
    }
    return {};
}

IoError read_certificate(const std::string& path, Certificate& out) {
    out = Certificate{};
    std::ifstream in(path, std::ios::binary);
    if (!in) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return {IoError::Code::CannotOpen, "cannot read '" + path + "'", 0};
    IoError e = parse_certificate(text.data(), text.size(), out);
    if (!e.ok()) e.message = path + ": " + e.message;
    return e;
}

IoError write_certificate(const std::string& path, const Certificate& c) {
    const Input& m = c.map;
    if (m.uvs.size() != 3 * m.triangles.size())
        return {IoError::Code::CannotWrite, "the certificate for '" + path + "' has no map (3 UVs per triangle)", 0};
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return {IoError::Code::CannotWrite, "cannot write '" + tmp + "'", 0};
    std::fprintf(f, "%s\n# grid_scale %d\n# repaired %zu\n", kMagic, c.grid_scale, c.repaired.size());
    for (std::size_t i = 0; i < c.repaired.size(); ++i)
        std::fprintf(f, "%s%" PRId32 "%s", i % kPerLine == 0 ? "# r " : "", c.repaired[i],
                     i % kPerLine == kPerLine - 1 || i + 1 == c.repaired.size() ? "\n" : " ");
    std::fprintf(f, "# the map: its positions and triangles as given, the repaired map's UVs per corner\n");
    for (const auto& p : m.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    for (const auto& uv : m.uvs) std::fprintf(f, "vt %.17g %.17g\n", uv[0], uv[1]);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& tri = m.triangles[t];
        std::fprintf(f, "f %d/%zu %d/%zu %d/%zu\n", tri[0] + 1, 3 * t + 1, tri[1] + 1, 3 * t + 2, tri[2] + 1,
                     3 * t + 3);
    }
    return io_detail::close_and_rename(f, tmp, path);
}

} // namespace qex
