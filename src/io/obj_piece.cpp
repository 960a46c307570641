// Parsing one piece of an OBJ map: `v`, `vt` and triangular `f v/vt[/vn]` records, records
// without meaning for the map skipped, and the first problem recorded with its line in the piece.
#include "io/obj_piece.h"

#include "io/checked_int.h"
#include "io/text_cursor.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

namespace qex::io_detail {
namespace {

/// Records the piece's first problem on the cursor's line; returns false (parsing stops there).
bool fail(Piece& piece, const Cursor& c, IoError::Code code, std::string msg) {
    piece.failed = true;
    piece.code = code;
    piece.error_line = c.line;
    piece.error = std::move(msg);
    return false;
}

/// The N numbers of a `v` or `vt` record after its key, an optional weight after them, all
/// finite; appended to `to`. False on a problem.
template <std::size_t N>
bool read_coordinates(Cursor& c, Piece& piece, std::vector<std::array<double, N>>& to, const char* key) {
    std::array<double, N> x{};
    for (double& xi : x)
        if (!c.read_double(xi))
            return fail(piece, c, IoError::Code::Syntax,
                        "expected " + std::to_string(N) + " numbers after '" + key + "'");
    double w;
    if (!c.at_eol() && !c.read_double(w))
        return fail(piece, c, IoError::Code::Syntax, std::string("malformed '") + key + "' record");
    for (double xi : x)
        if (!std::isfinite(xi))
            return fail(piece, c, IoError::Code::NonFinite,
                        N == 3 ? "non-finite vertex coordinate" : "non-finite texture coordinate");
    to.push_back(x);
    return true;
}

/// One `v/vt` or `v/vt/vn` corner of a face (the normal index is read and ignored), ending at a
/// blank, line end or comment. False on a problem.
bool read_corner(Cursor& c, Piece& piece, std::int64_t& v, std::int64_t& t) {
    const char* const no_uv = "face corner without a texture coordinate (expected v/vt)";
    const auto too_long = [&](const char* what) { // an index of too many digits for any file
        return fail(piece, c, IoError::Code::IndexOutOfRange,
                    std::string(what) + " index " + c.too_long_integer() + " out of range");
    };
    if (!c.read_int(v))
        return c.too_long_integer().empty() ? fail(piece, c, IoError::Code::Syntax, "malformed face corner")
                                            : too_long("vertex");
    if (c.p >= c.end || *c.p != '/') return fail(piece, c, IoError::Code::MissingUv, no_uv);
    ++c.p;
    if (!c.read_int(t))
        return c.too_long_integer().empty() ? fail(piece, c, IoError::Code::MissingUv, no_uv) : too_long("texture");
    if (c.p < c.end && *c.p == '/') { // normal index, ignored
        ++c.p;
        std::int64_t nidx;
        if (!c.read_int(nidx)) return fail(piece, c, IoError::Code::Syntax, "malformed normal index");
    }
    if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\r' && *c.p != '\n' && *c.p != '#')
        return fail(piece, c, IoError::Code::Syntax, "malformed face corner");
    return true;
}

/// An `f` record after its key: exactly three corners, each index within 32 bits, kept as
/// written with the piece's record counts so far. False on a problem.
bool read_face(Cursor& c, Piece& piece) {
    Piece::Face face{};
    int n = 0;
    while (!c.at_eol()) {
        std::int64_t v = 0, t = 0;
        if (!read_corner(c, piece, v, t)) return false;
        if (n == 3)
            return fail(piece, c, IoError::Code::NonTriangle,
                        "face with more than 3 corners (only triangles are accepted)");
        // Beyond 32 bits an index is out of range of any file this reader accepts (and -2^31,
        // whose negation, a relative index's distance, would not fit either).
        if (v < -INT32_MAX || !checked_int(v, face.v[n]))
            return fail(piece, c, IoError::Code::IndexOutOfRange,
                        "vertex index " + std::to_string(v) + " out of range");
        if (t < -INT32_MAX || !checked_int(t, face.t[n]))
            return fail(piece, c, IoError::Code::IndexOutOfRange,
                        "texture index " + std::to_string(t) + " out of range");
        ++n;
    }
    if (n != 3)
        return fail(piece, c, IoError::Code::NonTriangle,
                    "face with " + std::to_string(n) + " corners (only triangles are accepted)");
    face.line = static_cast<std::int32_t>(c.line);
    face.nv = static_cast<std::int32_t>(piece.positions.size());
    face.nvt = static_cast<std::int32_t>(piece.vts.size());
    piece.faces.push_back(face);
    return true;
}

/// What became of a record.
enum class Record { Read, Skipped, Failed };

/// The record named `key` (the cursor just after the key): read into `piece`, skipped with the
/// rest of its line if it means nothing for the map, or failed (an unknown key or a problem).
Record read_record(Cursor& c, std::string_view key, Piece& piece) {
    if (key == "v") return read_coordinates(c, piece, piece.positions, "v") ? Record::Read : Record::Failed;
    if (key == "vt") return read_coordinates(c, piece, piece.vts, "vt") ? Record::Read : Record::Failed;
    if (key == "f") return read_face(c, piece) ? Record::Read : Record::Failed;
    if (key == "vn" || key == "vp" || key == "o" || key == "g" || key == "s" || key == "usemtl" || key == "mtllib" ||
        key == "l") {
        c.skip_line(); // records without meaning for the map
        return Record::Skipped;
    }
    fail(piece, c, IoError::Code::Syntax, "unknown record '" + std::string(key.substr(0, 32)) + "'");
    return Record::Failed;
}

} // namespace

void parse_piece(const char* begin, const char* end, Piece& piece) {
    Cursor c{begin, end, 1};
    while (c.p < c.end) {
        c.skip_blanks();
        if (c.p >= c.end) break;
        const char ch = *c.p;
        if (ch == '\n') {
            ++c.p;
            ++c.line;
            continue;
        }
        if (ch == '#') {
            c.skip_line();
            continue;
        }
        const std::string_view key = c.read_key();
        const Record record = read_record(c, key, piece);
        if (record == Record::Failed) return;
        if (record == Record::Skipped) continue;
        if (!c.at_eol()) {
            fail(piece, c, IoError::Code::Syntax, "trailing characters");
            return;
        }
        if (c.p < c.end && *c.p == '#') {
            c.skip_line();
            continue;
        }
        if (c.p < c.end) {
            ++c.p;
            ++c.line;
        }
    }
    piece.lines = c.line - 1;
}

} // namespace qex::io_detail
