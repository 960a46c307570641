// OBJ and VVAL files: a single-pass reader over the whole buffer (fast_float for numbers) that
// reports the line of every problem, and a writer that renames a finished temporary file into place.
#include "qex/qex.h"

#include <fast_float/fast_float.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace qex {
namespace {

struct Cursor {
    const char* p;
    const char* end;
    std::int64_t line = 1;

    void skip_blanks() { while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p; }
    bool at_eol() { skip_blanks(); return p >= end || *p == '\n' || *p == '#'; }
    void skip_line() {
        const void* nl = std::memchr(p, '\n', static_cast<std::size_t>(end - p));
        p = nl ? static_cast<const char*>(nl) + 1 : end;
        ++line;
    }
    bool read_double(double& x) {
        skip_blanks();
        const char* start = p;
        if (p < end && *p == '+') ++p; // fast_float does not take a leading '+'
        auto r = fast_float::from_chars(p, end, x);
        if (r.ec != std::errc() || r.ptr == p) { p = start; return false; }
        p = r.ptr;
        return p >= end || *p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '#';
    }
    bool read_int(std::int64_t& x) {
        const char* start = p;
        bool neg = false;
        if (p < end && (*p == '-' || *p == '+')) neg = *p++ == '-';
        std::int64_t v = 0;
        const char* digits = p;
        while (p < end && *p >= '0' && *p <= '9') {
            if (v > (std::int64_t{1} << 40)) { p = start; return false; }
            v = v * 10 + (*p++ - '0');
        }
        if (p == digits) { p = start; return false; }
        x = neg ? -v : v;
        return true;
    }
};

IoError err(IoError::Code c, std::int64_t line, const std::string& msg) {
    return {c, "line " + std::to_string(line) + ": " + msg, line};
}

/// Resolves a 1-based (or negative, relative) OBJ index against `count` elements.
bool resolve(std::int64_t idx, std::size_t count, int& out) {
    const auto n = static_cast<std::int64_t>(count);
    if (idx > 0 && idx <= n) { out = static_cast<int>(idx - 1); return true; }
    if (idx < 0 && -idx <= n) { out = static_cast<int>(n + idx); return true; }
    return false;
}

bool read_file(const std::string& path, std::string& data) {
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

} // namespace

namespace {

/// The OBJ reader's state across chunks of a file (each chunk ends at a line end, or is the last).
/// Triangles are stored as they come; corner UVs are looked up once every `vt` is known.
class ObjParser {
public:
    explicit ObjParser(Input& out) : out_(out) { out_ = Input{}; }

    IoError feed(const char* data, std::size_t size) {
        Cursor c{data, data + size, line_};
        IoError e = parse(c);
        line_ = c.line;
        return e;
    }

    void finish() {
        out_.uvs.resize(tex_.size());
        for (std::size_t i = 0; i < tex_.size(); ++i) out_.uvs[i] = vts_[static_cast<std::size_t>(tex_[i])];
        std::vector<int>().swap(tex_);
        std::vector<std::array<double, 2>>().swap(vts_);
    }

private:
    /// The N numbers of a `v` or `vt` record, an optional weight after them, all finite.
    template <std::size_t N>
    static IoError read_record(Cursor& c, std::array<double, N>& x, const char* key, const char* what) {
        for (double& xi : x)
            if (!c.read_double(xi))
                return err(IoError::Code::Syntax, c.line, "expected " + std::to_string(N) + " numbers after '" + key + "'");
        double w;
        if (!c.at_eol() && !c.read_double(w)) return err(IoError::Code::Syntax, c.line, std::string("malformed '") + key + "' record");
        for (double xi : x)
            if (!std::isfinite(xi)) return err(IoError::Code::NonFinite, c.line, std::string("non-finite ") + what);
        return {};
    }

    IoError parse(Cursor& c) {
        Input& out = out_;
        while (c.p < c.end) {
            c.skip_blanks();
            if (c.p >= c.end) break;
            const char ch = *c.p;
            if (ch == '\n') { ++c.p; ++c.line; continue; }
            if (ch == '#') { c.skip_line(); continue; }
            const char* kw = c.p;
            while (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\n' && *c.p != '\r') ++c.p;
            const std::string_view key(kw, static_cast<std::size_t>(c.p - kw));
            if (key == "v") {
                std::array<double, 3> p{};
                if (IoError e = read_record(c, p, "v", "vertex coordinate"); !e.ok()) return e;
                out.positions.push_back(p);
            } else if (key == "vt") {
                std::array<double, 2> t{};
                if (IoError e = read_record(c, t, "vt", "texture coordinate"); !e.ok()) return e;
                vts_.push_back(t);
            } else if (key == "f") {
                std::array<std::int64_t, 3> fv{}, ft{};
                int n = 0;
                while (!c.at_eol()) {
                    std::int64_t v = 0, t = 0;
                    if (!c.read_int(v)) return err(IoError::Code::Syntax, c.line, "malformed face corner");
                    if (c.p >= c.end || *c.p != '/')
                        return err(IoError::Code::MissingUv, c.line, "face corner without a texture coordinate (expected v/vt)");
                    ++c.p;
                    if (!c.read_int(t))
                        return err(IoError::Code::MissingUv, c.line, "face corner without a texture coordinate (expected v/vt)");
                    if (c.p < c.end && *c.p == '/') { // normal index, ignored
                        ++c.p;
                        std::int64_t nidx;
                        if (!c.read_int(nidx)) return err(IoError::Code::Syntax, c.line, "malformed normal index");
                    }
                    if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\r' && *c.p != '\n' && *c.p != '#')
                        return err(IoError::Code::Syntax, c.line, "malformed face corner");
                    if (n == 3) return err(IoError::Code::NonTriangle, c.line, "face with more than 3 corners (only triangles are accepted)");
                    fv[n] = v;
                    ft[n++] = t;
                }
                if (n != 3)
                    return err(IoError::Code::NonTriangle, c.line, "face with " + std::to_string(n) + " corners (only triangles are accepted)");
                // OBJ allows relative indices: resolve against the counts seen so far.
                std::array<int, 3> tri{}, tex{};
                for (int k = 0; k < 3; ++k) {
                    if (!resolve(fv[k], out.positions.size(), tri[k]))
                        return err(IoError::Code::IndexOutOfRange, c.line, "vertex index " + std::to_string(fv[k]) + " out of range");
                    if (!resolve(ft[k], vts_.size(), tex[k]))
                        return err(IoError::Code::IndexOutOfRange, c.line, "texture index " + std::to_string(ft[k]) + " out of range");
                }
                out.triangles.push_back(tri);
                tex_.insert(tex_.end(), tex.begin(), tex.end());
            } else if (key == "vn" || key == "vp" || key == "o" || key == "g" || key == "s" || key == "usemtl" ||
                       key == "mtllib" || key == "l") {
                c.skip_line(); // records without meaning for the map
                continue;
            } else {
                return err(IoError::Code::Syntax, c.line, "unknown record '" + std::string(key.substr(0, 32)) + "'");
            }
            if (!c.at_eol()) return err(IoError::Code::Syntax, c.line, "trailing characters");
            if (c.p < c.end && *c.p == '#') { c.skip_line(); continue; }
            if (c.p < c.end) { ++c.p; ++c.line; }
        }
        return {};
    }

    Input& out_;
    std::vector<std::array<double, 2>> vts_;
    std::vector<int> tex_; // per corner: index into vts_
    std::int64_t line_ = 1;
};

} // namespace

IoError parse_obj(const char* data, std::size_t size, Input& out) {
    ObjParser parser(out);
    if (IoError e = parser.feed(data, size); !e.ok()) return e;
    parser.finish();
    return {};
}

IoError read_obj(const std::string& path, Input& out) {
    // Chunks of about 4 MiB, each cut after its last line end, so a large file is never held
    // whole in memory.
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    ObjParser parser(out);
    std::string buf;
    std::size_t kept = 0; // bytes of an unfinished line carried over
    IoError result;
    for (;;) {
        const std::size_t chunk = std::size_t{1} << 22;
        buf.resize(kept + chunk);
        const std::size_t n = std::fread(&buf[kept], 1, chunk, f);
        const std::size_t have = kept + n;
        if (n == 0) {
            if (std::ferror(f)) result = {IoError::Code::CannotOpen, "cannot read '" + path + "'", 0};
            else if (have > 0) result = parser.feed(buf.data(), have);
            break;
        }
        const void* last = nullptr;
        for (std::size_t i = have; i > kept && !last; --i)
            if (buf[i - 1] == '\n') last = &buf[i - 1];
        if (!last) { // no line end in the new bytes: the line goes on
            kept = have;
            continue;
        }
        const std::size_t upto = static_cast<std::size_t>(static_cast<const char*>(last) - buf.data()) + 1;
        if (result = parser.feed(buf.data(), upto); !result.ok()) break;
        kept = have - upto;
        std::memmove(&buf[0], &buf[upto], kept);
    }
    std::fclose(f);
    if (!result.ok()) {
        out = Input{};
        return result;
    }
    parser.finish();
    return {};
}

IoError parse_vval(const char* data, std::size_t size, std::vector<int>& valences) {
    valences.clear();
    Cursor c{data, data + size};
    // Line 1: the JSON header.
    const char* nl = static_cast<const char*>(std::memchr(data, '\n', size));
    const std::string header(data, nl ? nl : data + size);
    if (header.find("\"VVAL\"") == std::string::npos)
        return err(IoError::Code::VvalSyntax, 1, "expected the header {\"file_format\":\"VVAL\",\"version\":1}");
    c.skip_line();
    std::int64_t count = -1;
    while (c.p < c.end) {
        c.skip_blanks();
        if (c.p < c.end && *c.p == '\n') { ++c.p; ++c.line; continue; }
        if (c.p >= c.end) break;
        std::int64_t x;
        if (!c.read_int(x)) return err(IoError::Code::VvalSyntax, c.line, "expected an integer");
        if (count < 0) {
            if (x < 0 || x > (std::int64_t{1} << 30)) return err(IoError::Code::VvalSyntax, c.line, "implausible vertex count");
            count = x;
            valences.reserve(static_cast<std::size_t>(std::min<std::int64_t>(count, 1 << 24)));
        } else {
            if (x < 0 || x > 1000) return err(IoError::Code::VvalSyntax, c.line, "implausible valence");
            valences.push_back(static_cast<int>(x));
        }
        if (!c.at_eol()) return err(IoError::Code::VvalSyntax, c.line, "trailing characters");
    }
    if (count < 0) return err(IoError::Code::VvalSyntax, c.line, "missing vertex count");
    if (static_cast<std::int64_t>(valences.size()) != count)
        return err(IoError::Code::VvalSyntax, c.line,
                   "expected " + std::to_string(count) + " valences, found " + std::to_string(valences.size()));
    return {};
}

IoError read_vval(const std::string& path, std::vector<int>& valences) {
    std::string data;
    if (!read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    return parse_vval(data.data(), data.size(), valences);
}

IoError write_obj(const std::string& path, const QuadMesh& mesh) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return {IoError::Code::CannotWrite, "cannot write '" + tmp + "'", 0};
    std::string buf;
    buf.reserve(1 << 16);
    char line[160];
    auto flush = [&](bool force) {
        if (buf.size() > (1 << 15) || force) {
            std::fwrite(buf.data(), 1, buf.size(), f);
            buf.clear();
        }
    };
    buf += "# qex quad mesh: " + std::to_string(mesh.positions.size()) + " vertices, " +
           std::to_string(mesh.faces.size()) + " faces\n";
    for (const auto& p : mesh.positions) {
        buf.append(line, static_cast<std::size_t>(std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], p[2])));
        flush(false);
    }
    const bool uvs = mesh.face_uvs.size() == mesh.faces.size();
    for (std::size_t i = 0; uvs && i < mesh.faces.size(); ++i)
        for (const auto& t : mesh.face_uvs[i]) {
            buf.append(line, static_cast<std::size_t>(std::snprintf(line, sizeof line, "vt %lld %lld\n",
                                                                    static_cast<long long>(t[0]), static_cast<long long>(t[1]))));
            flush(false);
        }
    std::size_t t = 1;
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        buf += 'f';
        for (std::size_t k = 0; k < mesh.faces[i].size(); ++k) {
            if (uvs && k < mesh.face_uvs[i].size())
                buf.append(line, static_cast<std::size_t>(std::snprintf(line, sizeof line, " %d/%zu", mesh.faces[i][k] + 1, t++)));
            else
                buf.append(line, static_cast<std::size_t>(std::snprintf(line, sizeof line, " %d", mesh.faces[i][k] + 1)));
        }
        buf += '\n';
        flush(false);
    }
    flush(true);
    const bool ok = std::ferror(f) == 0;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(tmp.c_str());
        return {IoError::Code::CannotWrite, "error while writing '" + tmp + "'", 0};
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        return {IoError::Code::CannotWrite, "cannot rename '" + tmp + "' to '" + path + "'", 0};
    }
    return {};
}

IoError read_polygon_obj(const std::string& path, QuadMesh& out) {
    out = QuadMesh{};
    std::string data;
    if (!read_file(path, data)) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    Cursor c{data.data(), data.data() + data.size()};
    while (c.p < c.end) {
        c.skip_blanks();
        if (c.p >= c.end) break;
        if (*c.p == '\n') { ++c.p; ++c.line; continue; }
        if (*c.p == '#') { c.skip_line(); continue; }
        const char* kw = c.p;
        while (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\n' && *c.p != '\r') ++c.p;
        const std::string key(kw, c.p);
        if (key == "v") {
            std::array<double, 3> p{};
            for (double& x : p)
                if (!c.read_double(x)) return err(IoError::Code::Syntax, c.line, "expected 3 numbers after 'v'");
            out.positions.push_back(p);
        } else if (key == "f") {
            std::vector<int> face;
            while (!c.at_eol()) {
                std::int64_t v;
                if (!c.read_int(v)) return err(IoError::Code::Syntax, c.line, "malformed face corner");
                int vi;
                if (!resolve(v, out.positions.size(), vi))
                    return err(IoError::Code::IndexOutOfRange, c.line, "vertex index out of range");
                face.push_back(vi);
                while (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\r' && *c.p != '\n') ++c.p;
            }
            out.faces.push_back(std::move(face));
        }
        c.skip_line();
    }
    return {};
}

} // namespace qex
