// OBJ and VVAL files: a single-pass reader over the whole buffer (fast_float for numbers) that
// reports the line of every problem, and a writer that renames a finished temporary file into place.
#include "qex/io.h"

#include <fast_float/fast_float.h>
#include "extract/parallel.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>

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

/// What one piece of a file (a run of whole lines) holds, parsed without knowing what came
/// before it: face indices are kept as written, with the piece's own vertex counts at the face,
/// and lines are counted from the piece's start. Pieces are committed in file order.
struct Piece {
    struct Face {
        std::array<std::int32_t, 3> v, t; // as written (1-based or negative, relative)
        std::int32_t line;                // line in the piece (1 = its first)
        std::int32_t nv, nvt;             // `v` and `vt` records of the piece before the face
    };
    std::vector<std::array<double, 3>> positions;
    std::vector<std::array<double, 2>> vts;
    std::vector<Face> faces;
    std::int64_t lines = 0; ///< line ends consumed
    /// The piece's first problem (parsing stopped there), its line counted in the piece.
    bool failed = false;
    IoError::Code code = IoError::Code::Syntax;
    std::int64_t error_line = 0;
    std::string error;

};

/// The N numbers of a `v` or `vt` record, an optional weight after them, all finite. Returns
/// the problem, or an empty string.
template <std::size_t N>
std::string read_record(Cursor& c, std::array<double, N>& x, const char* key, IoError::Code& code) {
    code = IoError::Code::Syntax;
    for (double& xi : x)
        if (!c.read_double(xi)) return "expected " + std::to_string(N) + " numbers after '" + key + "'";
    double w;
    if (!c.at_eol() && !c.read_double(w)) return std::string("malformed '") + key + "' record";
    code = IoError::Code::NonFinite;
    for (double xi : x)
        if (!std::isfinite(xi)) return N == 3 ? "non-finite vertex coordinate" : "non-finite texture coordinate";
    return {};
}

/// Parses whole lines [begin, end) into `piece`, stopping at the first problem.
void parse_piece(const char* begin, const char* end, Piece& piece) {
    Cursor c{begin, end, 1};
    auto fail = [&](IoError::Code code, std::string msg) {
        piece.failed = true;
        piece.code = code;
        piece.error_line = c.line;
        piece.error = std::move(msg);
    };
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
            IoError::Code code;
            if (std::string e = read_record(c, p, "v", code); !e.empty()) return fail(code, std::move(e));
            piece.positions.push_back(p);
        } else if (key == "vt") {
            std::array<double, 2> t{};
            IoError::Code code;
            if (std::string e = read_record(c, t, "vt", code); !e.empty()) return fail(code, std::move(e));
            piece.vts.push_back(t);
        } else if (key == "f") {
            Piece::Face face{};
            int n = 0;
            while (!c.at_eol()) {
                std::int64_t v = 0, t = 0;
                if (!c.read_int(v)) return fail(IoError::Code::Syntax, "malformed face corner");
                if (c.p >= c.end || *c.p != '/')
                    return fail(IoError::Code::MissingUv, "face corner without a texture coordinate (expected v/vt)");
                ++c.p;
                if (!c.read_int(t))
                    return fail(IoError::Code::MissingUv, "face corner without a texture coordinate (expected v/vt)");
                if (c.p < c.end && *c.p == '/') { // normal index, ignored
                    ++c.p;
                    std::int64_t nidx;
                    if (!c.read_int(nidx)) return fail(IoError::Code::Syntax, "malformed normal index");
                }
                if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\r' && *c.p != '\n' && *c.p != '#')
                    return fail(IoError::Code::Syntax, "malformed face corner");
                if (n == 3) return fail(IoError::Code::NonTriangle, "face with more than 3 corners (only triangles are accepted)");
                // Beyond 32 bits an index is out of range of any file this reader accepts.
                if (v < -INT32_MAX || v > INT32_MAX)
                    return fail(IoError::Code::IndexOutOfRange, "vertex index " + std::to_string(v) + " out of range");
                if (t < -INT32_MAX || t > INT32_MAX)
                    return fail(IoError::Code::IndexOutOfRange, "texture index " + std::to_string(t) + " out of range");
                face.v[n] = static_cast<std::int32_t>(v);
                face.t[n++] = static_cast<std::int32_t>(t);
            }
            if (n != 3)
                return fail(IoError::Code::NonTriangle, "face with " + std::to_string(n) + " corners (only triangles are accepted)");
            face.line = static_cast<std::int32_t>(c.line);
            face.nv = static_cast<std::int32_t>(piece.positions.size());
            face.nvt = static_cast<std::int32_t>(piece.vts.size());
            piece.faces.push_back(face);
        } else if (key == "vn" || key == "vp" || key == "o" || key == "g" || key == "s" || key == "usemtl" ||
                   key == "mtllib" || key == "l") {
            c.skip_line(); // records without meaning for the map
            continue;
        } else {
            return fail(IoError::Code::Syntax, "unknown record '" + std::string(key.substr(0, 32)) + "'");
        }
        if (!c.at_eol()) return fail(IoError::Code::Syntax, "trailing characters");
        if (c.p < c.end && *c.p == '#') { c.skip_line(); continue; }
        if (c.p < c.end) { ++c.p; ++c.line; }
    }
    piece.lines = c.line - 1;
}

/// The OBJ reader's state across chunks of a file (each chunk ends at a line end, or is the last).
/// A chunk is cut into pieces at line ends, which are parsed on all threads and kept. Once the
/// file is read (or a piece failed), finish() sizes the arrays exactly, places every piece's
/// records and resolves its indices in parallel, and reports the first problem in file order:
/// the result and the problem are those of a serial read.
class ObjParser {
public:
    ObjParser(Input& out, int threads) : out_(out), threads_(threads) { out_ = Input{}; }

    /// Parses whole lines; false once a piece has failed (nothing after it matters).
    bool feed(const char* data, std::size_t size) {
        // Pieces of 256 KiB to 64 MiB, cut after a line end (a piece's line and record counts
        // then fit 32 bits), parsed `threads_` at a time.
        constexpr std::size_t kMinPiece = std::size_t{1} << 18, kMaxPiece = std::size_t{1} << 26;
        const std::size_t threads = static_cast<std::size_t>(threads_);
        std::size_t piece_size = std::max(kMinPiece, (size + threads - 1) / threads);
        piece_size = std::min(piece_size, kMaxPiece);
        const char* const end = data + size;
        for (const char* from = data; from < end && !failed_;) {
            std::vector<const char*> cut{from};
            while (cut.size() <= threads && cut.back() < end) {
                const char* at = static_cast<std::size_t>(end - cut.back()) <= piece_size ? end : cut.back() + piece_size;
                if (at < end) {
                    const void* nl = std::memchr(at, '\n', static_cast<std::size_t>(end - at));
                    at = nl ? static_cast<const char*>(nl) + 1 : end;
                }
                cut.push_back(at);
            }
            const std::size_t first = pieces_.size();
            const auto count = static_cast<std::int64_t>(cut.size() - 1);
            pieces_.resize(first + cut.size() - 1);
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, 1) num_threads(threads_) if (count > 1)
#endif
            for (std::int64_t i = 0; i < count; ++i) {
                const auto k = static_cast<std::size_t>(i);
                parse_piece(cut[k], cut[k + 1], pieces_[first + k]);
            }
            for (std::size_t k = first; k < pieces_.size(); ++k)
                if (pieces_[k].failed) {
                    pieces_.resize(k + 1); // later pieces are never reached by a serial read
                    failed_ = true;
                    break;
                }
            from = cut.back();
        }
        return !failed_;
    }

    /// Places the pieces' records and resolves face indices against the counts at each face;
    /// fills `out` or returns the first problem in file order, with its line in the file.
    IoError finish() {
        struct Place { std::size_t nv, nvt, nf; std::int64_t first_line; };
        const std::size_t n = pieces_.size();
        std::vector<Place> at(n + 1);
        at[0] = {0, 0, 0, 1};
        for (std::size_t k = 0; k < n; ++k) {
            const Piece& p = pieces_[k];
            at[k + 1] = {at[k].nv + p.positions.size(), at[k].nvt + p.vts.size(), at[k].nf + p.faces.size(),
                         at[k].first_line + p.lines};
        }
        std::vector<std::array<double, 2>> vts(at[n].nvt);
        std::vector<int> tex(3 * at[n].nf); // per corner: index into vts
        out_.positions.resize(at[n].nv);
        out_.triangles.resize(at[n].nf);
        std::vector<IoError> problem(n);
        const auto pieces = static_cast<std::int64_t>(n);
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (pieces > 1)
#endif
        for (std::int64_t i = 0; i < pieces; ++i) {
            const auto k = static_cast<std::size_t>(i);
            Piece& p = pieces_[k];
            const Place& place = at[k];
            std::copy(p.positions.begin(), p.positions.end(), out_.positions.begin() + static_cast<std::ptrdiff_t>(place.nv));
            std::copy(p.vts.begin(), p.vts.end(), vts.begin() + static_cast<std::ptrdiff_t>(place.nvt));
            const std::int64_t base = place.first_line - 1;
            for (std::size_t j = 0; j < p.faces.size() && problem[k].ok(); ++j) {
                const Piece::Face& f = p.faces[j];
                std::array<int, 3>& tri = out_.triangles[place.nf + j];
                int* corner = &tex[3 * (place.nf + j)];
                for (int c = 0; c < 3; ++c) {
                    // OBJ allows relative indices: resolved against the counts seen so far.
                    if (!resolve(f.v[c], place.nv + static_cast<std::size_t>(f.nv), tri[c])) {
                        problem[k] = err(IoError::Code::IndexOutOfRange, base + f.line,
                                         "vertex index " + std::to_string(f.v[c]) + " out of range");
                        break;
                    }
                    if (!resolve(f.t[c], place.nvt + static_cast<std::size_t>(f.nvt), corner[c])) {
                        problem[k] = err(IoError::Code::IndexOutOfRange, base + f.line,
                                         "texture index " + std::to_string(f.t[c]) + " out of range");
                        break;
                    }
                }
            }
            if (problem[k].ok() && p.failed) problem[k] = err(p.code, base + p.error_line, p.error);
            p = Piece{}; // its records are placed: release them now
        }
        std::vector<Piece>().swap(pieces_);
        for (IoError& e : problem)
            if (!e.ok()) {
                out_ = Input{};
                return std::move(e);
            }
        out_.uvs.resize(tex.size());
        const auto corners = static_cast<std::int64_t>(tex.size());
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads_) if (detail::run_parallel(threads_, static_cast<std::int64_t>(corners)))
#endif
        for (std::int64_t i = 0; i < corners; ++i)
            out_.uvs[static_cast<std::size_t>(i)] = vts[static_cast<std::size_t>(tex[static_cast<std::size_t>(i)])];
        return {};
    }

private:
    Input& out_;
    int threads_;
    std::vector<Piece> pieces_; ///< parsed, in file order; the last one may have failed
    bool failed_ = false;
};

} // namespace

/// Below this size a file is read serially: threads would save less than they cost to start,
/// and their allocations would come from arenas of their own that the extraction cannot reuse.
constexpr std::size_t kParallelFrom = std::size_t{8} << 20;

IoError parse_obj(const char* data, std::size_t size, Input& out, int threads) {
    ObjParser parser(out, size < kParallelFrom ? 1 : detail::thread_count(threads));
    parser.feed(data, size);
    return parser.finish();
}

IoError read_obj(const std::string& path, Input& out, int threads) {
    // Chunks of about 4 MiB, each cut after its last line end, so a large file is never held
    // whole in memory. With threads, the next chunk is read while the current one is parsed.
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    const int parse_threads = ec || bytes < kParallelFrom ? 1 : detail::thread_count(threads);
    ObjParser parser(out, parse_threads);
    constexpr std::size_t kChunk = std::size_t{1} << 22;
    // A byte buffer that does not clear what it allocates (a 4 MiB string would touch all of
    // its pages even for a small file).
    struct Buffer {
        std::unique_ptr<char[]> bytes;
        std::size_t used = 0, capacity = 0;
        char* data() { return bytes.get(); }
        std::size_t size() const { return used; }
        char& operator[](std::size_t i) { return bytes[i]; }
        void grow(std::size_t n) {
            if (n <= capacity) return;
            const std::size_t c = std::max(n, 2 * capacity);
            std::unique_ptr<char[]> fresh(new char[c]);
            if (used > 0) std::memcpy(fresh.get(), bytes.get(), used);
            bytes = std::move(fresh);
            capacity = c;
        }
        void assign(Buffer& from, std::size_t at, std::size_t n) {
            grow(n);
            if (n > 0) std::memcpy(bytes.get(), from.bytes.get() + at, n);
            used = n;
        }
        void swap(Buffer& o) {
            std::swap(bytes, o.bytes);
            std::swap(used, o.used);
            std::swap(capacity, o.capacity);
        }
    };
    // Appends up to one chunk to `b` (which keeps its first `front` bytes); returns the count.
    auto read_into = [&](Buffer& b, std::size_t front) {
        b.used = front;
        b.grow(front + kChunk);
        const std::size_t n = std::fread(b.data() + front, 1, kChunk, f);
        b.used = front + n;
        return n;
    };
    Buffer buf, next;
    std::size_t kept = 0; // bytes of an unfinished line at the front of buf
    std::size_t n = read_into(buf, 0);
    IoError result;
    for (;;) {
        const std::size_t have = buf.size();
        if (n == 0) {
            if (std::ferror(f)) result = {IoError::Code::CannotOpen, "cannot read '" + path + "'", 0};
            else if (have > 0) parser.feed(buf.data(), have);
            break;
        }
        std::size_t upto = 0; // just after the last line end among the new bytes
        for (std::size_t i = have; i > kept && upto == 0; --i)
            if (buf[i - 1] == '\n') upto = i;
        if (upto == 0) { // no line end in the new bytes: the line goes on
            kept = have;
            n = read_into(buf, have);
            continue;
        }
        kept = have - upto;
        next.assign(buf, upto, kept); // the unfinished line starts the next chunk
        std::size_t next_n = 0;
        struct Joined { // the reading thread is joined however this iteration ends
            std::thread thread;
            ~Joined() { if (thread.joinable()) thread.join(); }
        } reader;
        if (parse_threads > 1) {
            try {
                reader.thread = std::thread([&] { next_n = read_into(next, kept); });
            } catch (const std::system_error&) { // no thread to be had: read after parsing
            }
        }
        const bool go_on = parser.feed(buf.data(), upto);
        if (reader.thread.joinable()) reader.thread.join();
        else if (go_on) next_n = read_into(next, kept);
        if (!go_on) break; // a problem: finish() reports the first
        buf.swap(next);
        n = next_n;
    }
    std::fclose(f);
    if (!result.ok()) {
        out = Input{};
        return result;
    }
    return parser.finish();
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
    // Numbers go through std::to_chars: the shortest text that reads back to the same double.
    constexpr std::size_t kBlock = std::size_t{1} << 16, kRecord = 512; // a record is far shorter
    std::vector<char> buf(kBlock + kRecord);
    char* p = buf.data();
    auto flush = [&](bool force) {
        if (static_cast<std::size_t>(p - buf.data()) >= kBlock || force) {
            std::fwrite(buf.data(), 1, static_cast<std::size_t>(p - buf.data()), f);
            p = buf.data();
        }
    };
    auto put = [&](const char* text) { while (*text) *p++ = *text++; };
    auto number = [&](auto x) { p = std::to_chars(p, buf.data() + buf.size(), x).ptr; };
    put("# qex quad mesh: ");
    number(mesh.positions.size());
    put(" vertices, ");
    number(mesh.faces.size());
    put(" faces\n");
    for (const auto& x : mesh.positions) {
        put("v");
        for (double c : x) *p++ = ' ', number(c);
        *p++ = '\n';
        flush(false);
    }
    const bool uvs = mesh.face_uvs.size() == mesh.faces.size();
    for (std::size_t i = 0; uvs && i < mesh.faces.size(); ++i)
        for (const auto& t : mesh.face_uvs[i]) {
            put("vt ");
            number(static_cast<long long>(t[0]));
            *p++ = ' ';
            number(static_cast<long long>(t[1]));
            *p++ = '\n';
            flush(false);
        }
    std::size_t t = 1;
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        *p++ = 'f';
        for (std::size_t k = 0; k < mesh.faces[i].size(); ++k) {
            *p++ = ' ';
            number(mesh.faces[i][k] + 1);
            if (uvs && k < mesh.face_uvs[i].size()) *p++ = '/', number(t++);
            flush(false); // a face may have many corners
        }
        *p++ = '\n';
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
