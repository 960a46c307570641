// VVAL valence files: a JSON header line, the vertex count, then one valence per vertex.
#include "qex/io.h"

#include "io/checked_int.h"
#include "io/text_cursor.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace qex {

using io_detail::Cursor;
using io_detail::err;

namespace {

/// The VVAL records of `data` into `valences`, which may hold a part on a problem.
IoError parse_vval_records(const char* data, std::size_t size, std::vector<int>& valences) {
    Cursor c{data, data + size};
    // Line 1: the JSON header.
    const char* nl = size > 0 ? static_cast<const char*>(std::memchr(data, '\n', size)) : nullptr;
    const std::string header(data, nl ? nl : data + size);
    if (header.find("\"VVAL\"") == std::string::npos)
        return err(IoError::Code::VvalSyntax, 1, "expected the header {\"file_format\":\"VVAL\",\"version\":1}");
    c.skip_line();
    std::int64_t count = -1;
    while (c.p < c.end) {
        c.skip_blanks();
        if (c.p < c.end && *c.p == '\n') {
            ++c.p;
            ++c.line;
            continue;
        }
        if (c.p >= c.end) break;
        // An integer of too many digits for read_int() is out of range, not malformed.
        std::int64_t x = 0;
        const bool read = c.read_int(x);
        const std::string shown = read ? std::to_string(x) : c.too_long_integer();
        if (shown.empty()) return err(IoError::Code::VvalSyntax, c.line, "expected an integer");
        if (count < 0) {
            if (!read || x < 0 || x > (std::int64_t{1} << 30))
                return err(IoError::Code::VvalSyntax, c.line, "implausible vertex count " + shown);
            count = x;
            std::size_t room = 0;
            if (io_detail::checked_int(std::min<std::int64_t>(count, 1 << 24), room)) valences.reserve(room);
        } else {
            int valence = -1;
            if (!read || !io_detail::checked_int(x, valence) || valence < 0 || valence > 1000)
                return err(IoError::Code::VvalSyntax, c.line, "implausible valence " + shown);
            valences.push_back(valence);
        }
        if (!c.at_eol()) return err(IoError::Code::VvalSyntax, c.line, "trailing characters");
    }
    if (count < 0) return err(IoError::Code::VvalSyntax, c.line, "missing vertex count");
    if (static_cast<std::int64_t>(valences.size()) != count)
        return err(IoError::Code::VvalSyntax, c.line,
                   "expected " + std::to_string(count) + " valences, found " + std::to_string(valences.size()));
    return {};
}

} // namespace

IoError parse_vval(const char* data, std::size_t size, std::vector<int>& valences) {
    valences.clear();
    IoError e = parse_vval_records(data, size, valences);
    if (!e.ok()) valences.clear(); // nothing from a file with a problem
    return e;
}

IoError read_vval(const std::string& path, std::vector<int>& valences) {
    valences.clear();
    std::string data;
    if (!io_detail::read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    return parse_vval(data.data(), data.size(), valences);
}

} // namespace qex
