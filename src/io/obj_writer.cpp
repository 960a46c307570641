// Writing a quad mesh as OBJ: records formatted into a block buffer and written to a temporary
// file, which is renamed into place once complete (and removed on a problem), so no partial file
// is ever left at the path.
#include "qex/io.h"

#include "io/file_io.h"

#include <charconv>
#include <cstdio>
#include <string>
#include <vector>

namespace qex {
namespace {

/// An OBJ file being written through a block buffer. Numbers go through std::to_chars: the
/// shortest text that reads back to the same double, and plain decimals for integers.
class ObjWriter {
public:
    explicit ObjWriter(std::FILE* f) : f_(f), buf_(kBlock + kRecord), p_(buf_.data()) {}

    /// The comment line with the mesh's vertex and face counts.
    void header(const QuadMesh& mesh) {
        put("# qex quad mesh: ");
        number(mesh.positions.size());
        put(" vertices, ");
        number(mesh.faces.size());
        put(" faces\n");
    }

    /// A `v` record per vertex.
    void positions(const QuadMesh& mesh) {
        for (const auto& x : mesh.positions) {
            put("v");
            for (double c : x) *p_++ = ' ', number(c);
            *p_++ = '\n';
            flush(false);
        }
    }

    /// A `vt` record per face corner, faces in order, if every face has its UVs.
    void corner_uvs(const QuadMesh& mesh) {
        const bool uvs = with_uvs(mesh);
        for (std::size_t i = 0; uvs && i < mesh.faces.size(); ++i)
            for (const auto& t : mesh.face_uvs[i]) {
                put("vt ");
                number(static_cast<long long>(t[0]));
                *p_++ = ' ';
                number(static_cast<long long>(t[1]));
                *p_++ = '\n';
                flush(false);
            }
    }

    /// An `f` record per face; its corners name their `vt` records (in the order corner_uvs()
    /// wrote them) if every face has its UVs.
    void faces(const QuadMesh& mesh) {
        const bool uvs = with_uvs(mesh);
        std::size_t t = 1;
        for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
            *p_++ = 'f';
            for (std::size_t k = 0; k < mesh.faces[i].size(); ++k) {
                *p_++ = ' ';
                number(mesh.faces[i][k] + 1);
                if (uvs && k < mesh.face_uvs[i].size()) *p_++ = '/', number(t++);
                flush(false); // a face may have many corners
            }
            *p_++ = '\n';
            flush(false);
        }
    }

    /// Writes out what the buffer holds.
    void finish() { flush(true); }

private:
    static constexpr std::size_t kBlock = std::size_t{1} << 16, kRecord = 512; // a record is far shorter

    /// Whether the mesh has UVs for every face (else no `vt` records are written).
    static bool with_uvs(const QuadMesh& mesh) { return mesh.face_uvs.size() == mesh.faces.size(); }

    /// Writes out the buffer once it holds a block, or whatever it holds if `force`.
    void flush(bool force) {
        if (static_cast<std::size_t>(p_ - buf_.data()) >= kBlock || force) {
            std::fwrite(buf_.data(), 1, static_cast<std::size_t>(p_ - buf_.data()), f_);
            p_ = buf_.data();
        }
    }
    void put(const char* text) {
        while (*text) *p_++ = *text++;
    }
    template <class T>
    void number(T x) {
        p_ = std::to_chars(p_, buf_.data() + buf_.size(), x).ptr;
    }

    std::FILE* f_;
    std::vector<char> buf_;
    char* p_; ///< where the next character goes
};

} // namespace

namespace io_detail {

IoError close_and_rename(std::FILE* f, const std::string& tmp, const std::string& path) {
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

} // namespace io_detail

IoError write_obj(const std::string& path, const QuadMesh& mesh) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return {IoError::Code::CannotWrite, "cannot write '" + tmp + "'", 0};
    ObjWriter w(f);
    w.header(mesh);
    w.positions(mesh);
    w.corner_uvs(mesh);
    w.faces(mesh);
    w.finish();
    return io_detail::close_and_rename(f, tmp, path);
}

} // namespace qex
