// Polygon OBJ files (any quad mesh, e.g. one to check): `v` and `f` records, everything else
// skipped.
#include "qex/io.h"

#include "io/text_cursor.h"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace qex {
namespace {

using io_detail::Cursor;
using io_detail::err;

/// An `f` record after its key: a vertex index per corner, resolved against the vertices so
/// far; what follows an index's `/` up to the next blank (`/vt`, `/vt/vn`) is skipped. An index
/// is an integer: `1.5` or `2e3` is malformed, not vertex 1 or 2.
IoError read_polygon_face(Cursor& c, QuadMesh& out) {
    std::vector<int> face;
    const auto ends_index = [&c] {
        return c.p >= c.end || *c.p == '/' || *c.p == ' ' || *c.p == '\t' || *c.p == '\r' || *c.p == '\n' ||
               *c.p == '#';
    };
    while (!c.at_eol()) {
        std::int64_t v;
        if (!c.read_int(v)) {
            const std::string digits = c.too_long_integer(); // too many for any file: out of range
            if (digits.empty()) return err(IoError::Code::Syntax, c.line, "malformed face corner");
            return err(IoError::Code::IndexOutOfRange, c.line, "vertex index " + digits + " out of range");
        }
        if (!ends_index()) return err(IoError::Code::Syntax, c.line, "malformed face corner");
        int vi;
        if (!io_detail::resolve(v, out.positions.size(), vi))
            return err(IoError::Code::IndexOutOfRange, c.line,
                       "vertex index " + std::to_string(v) + " out of range (" + std::to_string(out.positions.size()) +
                           " vertices so far)");
        face.push_back(vi);
        while (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\r' && *c.p != '\n') ++c.p;
    }
    out.faces.push_back(std::move(face));
    return {};
}

/// The records of `data`, into `out` (which may hold a part on a problem).
IoError parse_polygon_obj(const std::string& data, QuadMesh& out) {
    Cursor c{data.data(), data.data() + data.size()};
    while (c.p < c.end) {
        c.skip_blanks();
        if (c.p >= c.end) break;
        if (*c.p == '\n') {
            ++c.p;
            ++c.line;
            continue;
        }
        if (*c.p == '#') {
            c.skip_line();
            continue;
        }
        const std::string_view key = c.read_key();
        if (key == "v") {
            std::array<double, 3> p{};
            for (double& x : p)
                if (!c.read_double(x)) return err(IoError::Code::Syntax, c.line, "expected 3 numbers after 'v'");
            out.positions.push_back(p);
        } else if (key == "f") {
            if (IoError e = read_polygon_face(c, out); !e.ok()) return e;
        }
        c.skip_line(); // the rest of the record, and any record without meaning here
    }
    return {};
}

} // namespace

IoError read_polygon_obj(const std::string& path, QuadMesh& out) {
    out = QuadMesh{};
    std::string data;
    if (!io_detail::read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    IoError e = parse_polygon_obj(data, out);
    if (!e.ok()) out = QuadMesh{}; // like every reader: nothing from a file with a problem
    return e;
}

} // namespace qex
