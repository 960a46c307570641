// PLY files (ASCII, binary little and big endian): the header's elements and properties, then
// their data, read value by value against the bytes left, so a count in the header never sizes
// an allocation beyond what the file can hold. Every problem names its place: the header line,
// or the byte offset and the element (and instance) being read.
#include "qex/io.h"

#include "io/checked_int.h"
#include "io/file_io.h"
#include "io/ply_values.h"
#include "io/text_cursor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace qex {
namespace {

using io_detail::PlyFormat;
using io_detail::PlyType;
using io_detail::ValueRead;
using io_detail::ValueReader;

struct Property {
    std::string name;
    bool list = false;
    PlyType count_type = PlyType::Uint8, type = PlyType::Float32;
};

struct Element {
    std::string name;
    std::int64_t count = 0;
    std::vector<Property> properties;
};

/// What the readers take from a PLY file.
struct PlyData {
    std::vector<std::array<double, 3>> positions;
    std::vector<std::array<double, 2>> vertex_uvs; ///< per vertex, when the vertices carry UVs
    std::vector<std::vector<int>> faces;
    std::vector<std::vector<double>> texcoords; ///< per face, when the faces carry a texcoord list
    bool has_vertex_uvs = false, has_texcoords = false;
};

IoError header_error(std::int64_t line, const std::string& msg) {
    return {IoError::Code::PlySyntax,
            (line > 0 ? "PLY header line " + std::to_string(line) : std::string("PLY header")) + ": " + msg, line};
}

/// Parses the header from `data`; on success `body` is where the data begin.
IoError parse_header(const char* data, std::size_t size, PlyFormat& format, std::vector<Element>& elements,
                     std::size_t& body) {
    io_detail::Cursor c{data, data + size};
    bool have_format = false;
    for (;;) {
        if (c.p >= c.end) return header_error(c.line, "the header ends without 'end_header'");
        const char* eol = static_cast<const char*>(std::memchr(c.p, '\n', static_cast<std::size_t>(c.end - c.p)));
        if (!eol) return header_error(c.line, "the header ends without 'end_header'");
        std::string_view line(c.p, static_cast<std::size_t>(eol - c.p));
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        std::vector<std::string_view> words;
        for (std::size_t i = 0; i < line.size();) {
            while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
            const std::size_t from = i;
            while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
            if (i > from) words.push_back(line.substr(from, i - from));
        }
        const std::int64_t number = c.line;
        c.p = eol + 1;
        ++c.line;
        if (number == 1) {
            if (words.size() != 1 || words[0] != "ply") return header_error(1, "not a PLY file (no 'ply' line)");
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        if (words[0] == "format") {
            if (words.size() != 3 || words[2] != "1.0") return header_error(number, "expected 'format <kind> 1.0'");
            if (words[1] == "ascii")
                format = PlyFormat::Ascii;
            else if (words[1] == "binary_little_endian")
                format = PlyFormat::BinaryLittle;
            else if (words[1] == "binary_big_endian")
                format = PlyFormat::BinaryBig;
            else
                return header_error(number, "unknown format '" + std::string(words[1]) + "'");
            have_format = true;
        } else if (words[0] == "element") {
            std::int64_t count = -1;
            io_detail::Cursor n{words.size() == 3 ? words[2].data() : nullptr,
                                words.size() == 3 ? words[2].data() + words[2].size() : nullptr};
            if (words.size() != 3 || !n.read_int(count) || n.p != n.end || count < 0 || count > INT32_MAX)
                return header_error(number, "expected 'element <name> <count>' with a count below 2^31");
            elements.push_back({std::string(words[1]), count, {}});
        } else if (words[0] == "property") {
            if (elements.empty()) return header_error(number, "a property before any element");
            Property prop;
            if (words.size() == 5 && words[1] == "list") {
                prop.list = true;
                if (!io_detail::parse_type(words[2], prop.count_type) || !io_detail::parse_type(words[3], prop.type))
                    return header_error(number, "unknown type in a list property");
                if (!io_detail::is_integer(prop.count_type))
                    return header_error(number, "a list's count must have an integer type");
                prop.name = std::string(words[4]);
            } else if (words.size() == 3) {
                if (!io_detail::parse_type(words[1], prop.type))
                    return header_error(number, "unknown type '" + std::string(words[1]) + "'");
                prop.name = std::string(words[2]);
            } else {
                return header_error(number,
                                    "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
            }
            elements.back().properties.push_back(prop);
        } else if (words[0] == "end_header") {
            if (words.size() != 1) return header_error(number, "trailing words after 'end_header'");
            if (!have_format) return header_error(number, "no 'format' line");
            body = static_cast<std::size_t>(c.p - data);
            return {};
        } else {
            return header_error(number, "unknown keyword '" + std::string(words[0]) + "'");
        }
    }
}

/// The index of the property named by one of `names` in `e`, or -1.
int find_property(const Element& e, std::initializer_list<const char*> names, bool list) {
    for (std::size_t i = 0; i < e.properties.size(); ++i)
        for (const char* n : names)
            if (e.properties[i].name == n && e.properties[i].list == list) return static_cast<int>(i);
    return -1;
}

/// Which properties of an element the readers take: the indices of x, y, z, the vertex UVs, the
/// face's index list and its texcoord list (-1: none), for the first vertex and face elements.
struct Roles {
    bool is_vertex = false, is_face = false;
    int px = -1, py = -1, pz = -1, pu = -1, pv = -1, pidx = -1, ptex = -1;
};

/// The roles of `el`'s properties; the first element named vertex must have x, y and z, the
/// first named face a vertex index list.
IoError find_roles(const Element& el, bool& seen_vertex, bool& seen_face, PlyData& out, Roles& roles) {
    roles.is_vertex = el.name == "vertex" && !seen_vertex;
    roles.is_face = el.name == "face" && !seen_face;
    if (roles.is_vertex) {
        seen_vertex = true;
        roles.px = find_property(el, {"x"}, false), roles.py = find_property(el, {"y"}, false);
        roles.pz = find_property(el, {"z"}, false);
        if (roles.px < 0 || roles.py < 0 || roles.pz < 0)
            return header_error(0, "element vertex has no x, y and z properties");
        roles.pu = find_property(el, {"s", "u", "texture_u", "texture_s"}, false);
        roles.pv = find_property(el, {"t", "v", "texture_v", "texture_t"}, false);
        out.has_vertex_uvs = roles.pu >= 0 && roles.pv >= 0;
    }
    if (roles.is_face) {
        seen_face = true;
        roles.pidx = find_property(el, {"vertex_indices", "vertex_index"}, true);
        if (roles.pidx < 0) return header_error(0, "element face has no vertex_indices list");
        roles.ptex = find_property(el, {"texcoord"}, true);
        out.has_texcoords = roles.ptex >= 0;
    }
    return {};
}

/// One instance of a vertex or face element.
struct Instance {
    std::array<double, 3> pos{};
    std::array<double, 2> uv{};
    std::vector<int> face;
    std::vector<double> tex;
};

/// Why a value read as `got` (not Ok) is refused: "missing or malformed list count", or
/// "list count inf does not fit its type uint8".
std::string refusal(ValueRead got, const char* what, double x, PlyType t) {
    if (got == ValueRead::Missing) return std::string("missing or malformed ") + what;
    return std::string(what) + " " + io_detail::number_text(x) + " does not fit its type " + io_detail::type_name(t);
}

/// Reads instance `i` of `el`, keeping the values of the properties with a role. Every number
/// that becomes an integer (a list's count, a vertex index) goes through checked_int().
IoError read_instance(ValueReader& r, const Element& el, std::int64_t i, const Roles& roles, Instance& in) {
    for (std::size_t k = 0; k < el.properties.size(); ++k) {
        const Property& p = el.properties[k];
        const auto fail = [&](const std::string& what) {
            return IoError{IoError::Code::PlySyntax,
                           "byte " + std::to_string(r.offset()) + ": element " + el.name + " " + std::to_string(i) +
                               ", property " + p.name + ": " + what,
                           0, r.offset()};
        };
        double x = 0;
        ValueRead got = ValueRead::Ok;
        if (!p.list) {
            if ((got = r.read(p.type, x)) != ValueRead::Ok) return fail(refusal(got, "value", x, p.type));
            const int ki = static_cast<int>(k);
            if (ki == roles.px || ki == roles.py || ki == roles.pz)
                in.pos[ki == roles.px ? 0 : ki == roles.py ? 1 : 2] = x;
            if (ki == roles.pu) in.uv[0] = x;
            if (ki == roles.pv) in.uv[1] = x;
            continue;
        }
        double n = 0;
        std::int64_t count = -1;
        if ((got = r.read(p.count_type, n)) != ValueRead::Ok) return fail(refusal(got, "list count", n, p.count_type));
        if (!io_detail::checked_int(n, count) || count < 0)
            return fail("list count " + io_detail::number_text(n) + " out of range");
        // A count is below 2^32 here (its type has 32 bits at most): the product cannot overflow.
        if (static_cast<std::uint64_t>(count) * r.min_size(p.type) > r.left())
            return fail("a list of " + std::to_string(count) + " values runs past the end");
        const bool indices = static_cast<int>(k) == roles.pidx, texcoords = static_cast<int>(k) == roles.ptex;
        for (std::int64_t j = 0; j < count; ++j) {
            if ((got = r.read(p.type, x)) == ValueRead::Missing) return fail("missing or malformed list value");
            if (indices) {
                int v = -1;
                if (got != ValueRead::Ok || !io_detail::checked_int(x, v) || v < 0)
                    return fail("vertex index " + io_detail::number_text(x) +
                                (x == std::trunc(x) ? " out of range" : " is not an integer"));
                in.face.push_back(v);
            } else if (got != ValueRead::Ok) {
                return fail(refusal(got, "list value", x, p.type));
            }
            if (texcoords) in.tex.push_back(x);
        }
    }
    return {};
}

/// Reads every instance of `el`, keeping the vertices and faces.
IoError read_element(ValueReader& r, const Element& el, const Roles& roles, PlyData& out) {
    if (el.properties.empty()) return {}; // instances without properties take no bytes
    // Each instance takes at least a byte per property: a count the file cannot hold is an error now.
    std::size_t least = 0;
    for (const Property& p : el.properties) least += r.min_size(p.list ? p.count_type : p.type);
    if (least > 0 && static_cast<std::size_t>(el.count) > r.left() / least + 1)
        return {IoError::Code::PlySyntax,
                "byte " + std::to_string(r.offset()) + ": element " + el.name + ": " + std::to_string(el.count) +
                    " instances cannot fit in the " + std::to_string(r.left()) + " bytes left",
                0, r.offset()};
    for (std::int64_t i = 0; i < el.count; ++i) {
        Instance in;
        if (IoError e = read_instance(r, el, i, roles, in); !e.ok()) return e;
        if (roles.is_vertex) {
            out.positions.push_back(in.pos);
            if (out.has_vertex_uvs) out.vertex_uvs.push_back(in.uv);
        }
        if (roles.is_face) {
            out.faces.push_back(std::move(in.face));
            if (out.has_texcoords) out.texcoords.push_back(std::move(in.tex));
        }
    }
    return {};
}

/// Indices refer to the vertices (which may come after the faces in the file): each must name one.
IoError check_indices(const PlyData& out) {
    for (std::size_t f = 0; f < out.faces.size(); ++f)
        for (int v : out.faces[f])
            if (static_cast<std::size_t>(v) >= out.positions.size())
                return {IoError::Code::IndexOutOfRange,
                        "face " + std::to_string(f) + ": vertex index " + std::to_string(v) + " out of range (" +
                            std::to_string(out.positions.size()) + " vertices)",
                        0};
    return {};
}

/// The header, then the data: the vertices and faces of the file, checked.
IoError parse_data(const char* data, std::size_t size, PlyData& out) {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<Element> elements;
    std::size_t body = 0;
    if (IoError e = parse_header(data, size, format, elements, body); !e.ok()) return e;
    ValueReader r(data, data + body, data + size, format);
    bool seen_vertex = false, seen_face = false;
    for (const Element& el : elements) {
        Roles roles;
        if (IoError e = find_roles(el, seen_vertex, seen_face, out, roles); !e.ok()) return e;
        if (IoError e = read_element(r, el, roles, out); !e.ok()) return e;
    }
    if (format == PlyFormat::Ascii ? !r.only_blanks_left() : r.left() != 0)
        return {IoError::Code::PlySyntax, "byte " + std::to_string(r.offset()) + ": data after the last element", 0,
                r.offset()};
    if (!seen_vertex) return header_error(0, "no vertex element");
    if (!seen_face) return header_error(0, "no face element");
    return check_indices(out);
}

/// The PLY's triangles and per-corner UVs as a map.
IoError to_input(PlyData& d, Input& out) {
    if (!d.has_texcoords && !d.has_vertex_uvs)
        return {IoError::Code::MissingUv, "no UVs: neither a face texcoord list nor vertex s/t (u/v) properties", 0};
    for (std::size_t i = 0; i < d.positions.size(); ++i)
        for (double x : d.positions[i])
            if (!std::isfinite(x))
                return {IoError::Code::NonFinite, "vertex " + std::to_string(i) + ": non-finite coordinate", 0};
    out.positions = std::move(d.positions);
    out.triangles.resize(d.faces.size());
    out.uvs.resize(3 * d.faces.size());
    for (std::size_t f = 0; f < d.faces.size(); ++f) {
        const std::vector<int>& face = d.faces[f];
        if (face.size() != 3)
            return {
                IoError::Code::NonTriangle,
                "face " + std::to_string(f) + " has " + std::to_string(face.size()) + " vertices (a map has triangles)",
                0};
        if (d.has_texcoords && d.texcoords[f].size() != 6)
            return {IoError::Code::MissingUv,
                    "face " + std::to_string(f) + ": texcoord list has " + std::to_string(d.texcoords[f].size()) +
                        " values, expected 6 (u, v per corner)",
                    0};
        for (int k = 0; k < 3; ++k) {
            out.triangles[f][k] = face[k];
            std::array<double, 2> uv = d.has_texcoords
                                           ? std::array<double, 2>{d.texcoords[f][2 * k], d.texcoords[f][2 * k + 1]}
                                           : d.vertex_uvs[face[k]];
            if (!std::isfinite(uv[0]) || !std::isfinite(uv[1]))
                return {IoError::Code::NonFinite, "face " + std::to_string(f) + ": non-finite UV", 0};
            out.uvs[3 * f + k] = uv;
        }
    }
    return {};
}

} // namespace

IoError parse_ply(const char* data, std::size_t size, Input& out) {
    out = Input{};
    PlyData d;
    IoError e = parse_data(data, size, d);
    if (e.ok()) e = to_input(d, out);
    if (!e.ok()) out = Input{};
    return e;
}

IoError read_ply(const std::string& path, Input& out) {
    out = Input{};
    std::string data;
    if (!io_detail::read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    return parse_ply(data.data(), data.size(), out);
}

IoError parse_polygon_ply(const char* data, std::size_t size, QuadMesh& out) {
    out = QuadMesh{};
    PlyData d;
    IoError e = parse_data(data, size, d);
    if (!e.ok()) return e;
    out.positions = std::move(d.positions);
    out.faces = std::move(d.faces);
    return {};
}

IoError read_polygon_ply(const std::string& path, QuadMesh& out) {
    out = QuadMesh{};
    std::string data;
    if (!io_detail::read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    return parse_polygon_ply(data.data(), data.size(), out);
}

} // namespace qex
