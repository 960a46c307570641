// The OBJ map reader: a file is fed in chunks cut at line ends (a buffer as one chunk), each chunk
// cut into pieces that are parsed on several threads from 1 MiB of input (obj_piece.cpp), and the
// pieces' records placed in file order. The result, and the first problem with its line, are
// those of a serial read.
#include "qex/io.h"

#include "extract/parallel.h"
#include "io/obj_piece.h"
#include "io/text_cursor.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace qex {
namespace {

using io_detail::Piece;

/// Where a piece's records go: the `v`, `vt` and `f` records of all pieces before it, and the
/// line in the file of the piece's first line.
struct Place {
    std::size_t nv, nvt, nf;
    std::int64_t first_line;
};

/// The OBJ reader's state across chunks of a file (each chunk ends at a line end, or is the last).
/// A chunk is cut into pieces at line ends, which are parsed `threads_` at a time and kept. Once
/// the file is read (or a piece failed), finish() sizes the arrays exactly, places every piece's
/// records and resolves its indices in parallel, and reports the first problem in file order:
/// the result and the problem are those of a serial read.
class ObjParser {
public:
    ObjParser(Input& out, int threads) : out_(out), threads_(threads) { out_ = Input{}; }

    /// Parses a chunk; false once a piece has failed (nothing after it matters).
    bool feed(const char* data, std::size_t size) {
        // Pieces of a chunk's share per thread, but 256 KiB to 64 MiB, each extended to just
        // after a line end (a piece's line and record counts then fit 32 bits), parsed
        // `threads_` at a time.
        constexpr std::size_t kMinPiece = std::size_t{1} << 18, kMaxPiece = std::size_t{1} << 26;
        const std::size_t threads = static_cast<std::size_t>(threads_);
        std::size_t piece_size = std::max(kMinPiece, (size + threads - 1) / threads);
        piece_size = std::min(piece_size, kMaxPiece);
        const char* const end = data + size;
        for (const char* from = data; from < end && !failed_;) {
            const std::vector<const char*> cut = cut_pieces(from, end, piece_size);
            parse_pieces(cut);
            from = cut.back();
        }
        return !failed_;
    }

    /// Places the pieces' records and resolves face indices against the counts at each face;
    /// fills `out` or returns the first problem in file order, with its line in the file.
    IoError finish() {
        const std::vector<Place> at = places();
        const std::size_t n = pieces_.size();
        std::vector<std::array<double, 2>> vts(at[n].nvt);
        std::vector<int> tex(3 * at[n].nf); // per corner: index into vts
        out_.positions.resize(at[n].nv);
        out_.triangles.resize(at[n].nf);
        std::vector<IoError> problem(n);
        const auto pieces = static_cast<int>(n);
        detail::for_parts(threads_, pieces, pieces, [&](int i, std::int64_t, std::int64_t) {
            const auto k = static_cast<std::size_t>(i);
            problem[k] = place_piece(pieces_[k], at[k], vts, tex);
        });
        std::vector<Piece>().swap(pieces_);
        for (IoError& e : problem)
            if (!e.ok()) {
                out_ = Input{};
                return std::move(e);
            }
        gather_uvs(vts, tex);
        return {};
    }

private:
    /// Up to `threads_` pieces from `from` on: their bounds, each about `piece_size` bytes
    /// and ending after a line end (or at `end`).
    std::vector<const char*> cut_pieces(const char* from, const char* end, std::size_t piece_size) const {
        const std::size_t threads = static_cast<std::size_t>(threads_);
        std::vector<const char*> cut{from};
        while (cut.size() <= threads && cut.back() < end) {
            const char* at = static_cast<std::size_t>(end - cut.back()) <= piece_size ? end : cut.back() + piece_size;
            if (at < end) {
                const void* nl = std::memchr(at, '\n', static_cast<std::size_t>(end - at));
                at = nl ? static_cast<const char*>(nl) + 1 : end;
            }
            cut.push_back(at);
        }
        return cut;
    }

    /// Parses the pieces between the bounds `cut` in parallel and keeps them up to the first
    /// that failed.
    void parse_pieces(const std::vector<const char*>& cut) {
        const std::size_t first = pieces_.size();
        const auto count = static_cast<int>(cut.size() - 1);
        pieces_.resize(first + cut.size() - 1);
        detail::for_parts(threads_, count, count, [&](int i, std::int64_t, std::int64_t) {
            const auto k = static_cast<std::size_t>(i);
            io_detail::parse_piece(cut[k], cut[k + 1], pieces_[first + k]);
        });
        for (std::size_t k = first; k < pieces_.size(); ++k)
            if (pieces_[k].failed) {
                pieces_.resize(k + 1); // later pieces are never reached by a serial read
                failed_ = true;
                break;
            }
    }

    /// For each piece, and after the last: the records and lines of the pieces before it.
    std::vector<Place> places() const {
        const std::size_t n = pieces_.size();
        std::vector<Place> at(n + 1);
        at[0] = {0, 0, 0, 1};
        for (std::size_t k = 0; k < n; ++k) {
            const Piece& p = pieces_[k];
            at[k + 1] = {at[k].nv + p.positions.size(), at[k].nvt + p.vts.size(), at[k].nf + p.faces.size(),
                         at[k].first_line + p.lines};
        }
        return at;
    }

    /// Copies the piece's records to their place, resolves its faces' indices into `out_` and
    /// `tex`, then releases the piece. Returns its first problem, with its line in the file.
    IoError place_piece(Piece& p, const Place& place, std::vector<std::array<double, 2>>& vts, std::vector<int>& tex) {
        std::copy(p.positions.begin(), p.positions.end(),
                  out_.positions.begin() + static_cast<std::ptrdiff_t>(place.nv));
        std::copy(p.vts.begin(), p.vts.end(), vts.begin() + static_cast<std::ptrdiff_t>(place.nvt));
        const std::int64_t base = place.first_line - 1;
        IoError problem;
        for (std::size_t j = 0; j < p.faces.size() && problem.ok(); ++j)
            problem = resolve_face(p.faces[j], place, base, out_.triangles[place.nf + j], &tex[3 * (place.nf + j)]);
        if (problem.ok() && p.failed) problem = io_detail::err(p.code, base + p.error_line, p.error);
        p = Piece{}; // its records are placed: release them now
        return problem;
    }

    /// Resolves a face's vertex and texture indices into `tri` and `corner` against the records
    /// before it: those of the pieces before its own (`place`) and those of its own piece before
    /// it. `base` is the line in the file before the piece's first.
    static IoError resolve_face(const Piece::Face& f, const Place& place, std::int64_t base, std::array<int, 3>& tri,
                                int* corner) {
        for (int c = 0; c < 3; ++c) {
            // OBJ allows relative indices: resolved against the counts seen so far.
            if (!io_detail::resolve(f.v[c], place.nv + static_cast<std::size_t>(f.nv), tri[c]))
                return io_detail::err(IoError::Code::IndexOutOfRange, base + f.line,
                                      "vertex index " + std::to_string(f.v[c]) + " out of range");
            if (!io_detail::resolve(f.t[c], place.nvt + static_cast<std::size_t>(f.nvt), corner[c]))
                return io_detail::err(IoError::Code::IndexOutOfRange, base + f.line,
                                      "texture index " + std::to_string(f.t[c]) + " out of range");
        }
        return {};
    }

    /// The UV of every face corner, from the `vt` record it names.
    void gather_uvs(const std::vector<std::array<double, 2>>& vts, const std::vector<int>& tex) {
        out_.uvs.resize(tex.size());
        const auto corners = static_cast<std::int64_t>(tex.size());
        const int parts = detail::parts_for(threads_, corners);
        detail::for_parts(parts, parts, corners, [&](int, std::int64_t begin, std::int64_t end) {
            for (std::int64_t i = begin; i < end; ++i)
                out_.uvs[static_cast<std::size_t>(i)] = vts[static_cast<std::size_t>(tex[static_cast<std::size_t>(i)])];
        });
    }

    Input& out_;
    int threads_;
    std::vector<Piece> pieces_; ///< parsed, in file order; the last one may have failed
    bool failed_ = false;
};

/// A byte buffer that does not clear what it allocates (a 4 MiB string would touch all of
/// its pages even for a small file).
struct Buffer {
    std::unique_ptr<char[]> bytes;
    std::size_t used = 0, capacity = 0;
    char* data() { return bytes.get(); }
    std::size_t size() const { return used; }
    char& operator[](std::size_t i) { return bytes[i]; }
    /// Room for `n` bytes at least, keeping the bytes in use.
    void grow(std::size_t n) {
        if (n <= capacity) return;
        const std::size_t c = std::max(n, 2 * capacity);
        std::unique_ptr<char[]> fresh(new char[c]);
        if (used > 0) std::memcpy(fresh.get(), bytes.get(), used);
        bytes = std::move(fresh);
        capacity = c;
    }
    /// Holds `n` bytes of `from` from `at` on.
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

/// Feeds a file to the parser in chunks of about 4 MiB, each cut after its last line end, so a
/// large file is never held whole in memory. With `overlap`, the next chunk is read on a thread
/// of its own while the current one is parsed.
class ChunkedFeed {
public:
    ChunkedFeed(std::FILE* f, bool overlap) : f_(f), overlap_(overlap) {}

    /// Feeds the whole file, or up to the first piece that failed; false on a read error.
    bool run(ObjParser& parser) {
        std::size_t kept = 0; // bytes of an unfinished line at the front of buf_
        std::size_t n = read_into(buf_, 0);
        for (;;) {
            const std::size_t have = buf_.size();
            if (n == 0) {
                if (std::ferror(f_)) return false;
                if (have > 0) parser.feed(buf_.data(), have);
                return true;
            }
            const std::size_t upto = last_line_end(kept); // 0: none among the new bytes
            if (upto == 0) {                              // no line end in the new bytes: the line goes on
                kept = have;
                n = read_into(buf_, have);
                continue;
            }
            kept = have - upto;
            next_.assign(buf_, upto, kept); // the unfinished line starts the next chunk
            std::size_t next_n = 0;
            if (!feed_reading_next(parser, upto, kept, next_n)) return true; // finish() reports it
            buf_.swap(next_);
            n = next_n;
        }
    }

private:
    static constexpr std::size_t kChunk = std::size_t{1} << 22;

    /// Appends up to one chunk to `b` (which keeps its first `front` bytes); returns the count.
    std::size_t read_into(Buffer& b, std::size_t front) {
        b.used = front;
        b.grow(front + kChunk);
        const std::size_t n = std::fread(b.data() + front, 1, kChunk, f_);
        b.used = front + n;
        return n;
    }

    /// Just after the last line end in `buf_` from byte `from` on; 0 if there is none.
    std::size_t last_line_end(std::size_t from) {
        for (std::size_t i = buf_.size(); i > from; --i)
            if (buf_[i - 1] == '\n') return i;
        return 0;
    }

    /// Feeds the first `upto` bytes of `buf_` while the next chunk is read into `next_` after
    /// its first `kept` bytes, its byte count into `next_n`: on a thread if there is to be one,
    /// else after parsing, and not at all once a piece has failed. Returns the parser's verdict.
    bool feed_reading_next(ObjParser& parser, std::size_t upto, std::size_t kept, std::size_t& next_n) {
        struct Joined { // the reading thread is joined however this ends
            std::thread thread;
            ~Joined() {
                if (thread.joinable()) thread.join();
            }
        } reader;
        if (overlap_) {
            try {
                reader.thread = std::thread([&] { next_n = read_into(next_, kept); });
            } catch (const std::system_error&) { // no thread to be had: read after parsing
            }
        }
        const bool go_on = parser.feed(buf_.data(), upto);
        if (reader.thread.joinable())
            reader.thread.join();
        else if (go_on)
            next_n = read_into(next_, kept);
        return go_on;
    }

    std::FILE* f_;
    bool overlap_;
    Buffer buf_, next_;
};

/// Below this size an input is parsed serially: threads would save less than they cost to start.
/// From 1 MiB on two threads save time (the paper's 3 MB ducks: 6.3 -> 5 ms to read); the qex
/// program keeps one heap arena, so what the parser's threads free the extraction reuses.
constexpr std::size_t kParallelFrom = std::size_t{1} << 20;

} // namespace

IoError parse_obj(const char* data, std::size_t size, Input& out, int threads) {
    ObjParser parser(out, size < kParallelFrom ? 1 : detail::thread_count(threads));
    parser.feed(data, size);
    return parser.finish();
}

IoError read_obj(const std::string& path, Input& out, int threads) {
    out = Input{};
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return {IoError::Code::CannotOpen, "cannot open '" + path + "'", 0};
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    const int parse_threads = ec || bytes < kParallelFrom ? 1 : detail::thread_count(threads);
    ObjParser parser(out, parse_threads);
    const bool read = ChunkedFeed(f, parse_threads > 1).run(parser);
    std::fclose(f);
    if (!read) {
        out = Input{};
        return {IoError::Code::CannotOpen, "cannot read '" + path + "'", 0};
    }
    return parser.finish();
}

} // namespace qex
