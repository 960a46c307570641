// Writing a quad mesh as PLY: binary little endian (or ASCII), positions as doubles, each face's
// vertex list and its local UVs as a `texcoord` list (u, v per corner), through a temporary file
// renamed into place (removed on a problem), so no partial file is ever left.
#include "qex/io.h"

#include "io/file_io.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace qex {
namespace {

/// Bytes (binary) or text (ASCII) of the PLY data, little endian whatever the host.
class PlyOut {
public:
    explicit PlyOut(bool binary) : binary_(binary) {}
    template <class T>
    void value(T x) {
        if (binary_) {
            unsigned char b[sizeof(T)];
            std::memcpy(b, &x, sizeof x);
            if (io_detail::big_endian_host()) std::reverse(b, b + sizeof b);
            buf_.append(reinterpret_cast<const char*>(b), sizeof b);
        } else {
            char t[64];
            const auto r = std::to_chars(t, t + sizeof t, x);
            if (!at_line_start_) buf_ += ' ';
            buf_.append(t, r.ptr);
            at_line_start_ = false;
        }
    }
    void end_instance() {
        if (!binary_) buf_ += '\n', at_line_start_ = true;
    }
    std::string& text() { return buf_; }

private:
    bool binary_;
    bool at_line_start_ = true;
    std::string buf_;
};

} // namespace

IoError write_ply(const std::string& path, const QuadMesh& mesh, bool binary) {
    const bool uvs = mesh.face_uvs.size() == mesh.faces.size();
    std::size_t most = 0;
    for (const auto& f : mesh.faces) most = std::max(most, f.size());
    const bool wide = most > 255; // --poly meshes may have long faces: an int count then
    std::string header = "ply\nformat ";
    header += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
    header += "comment qex quad mesh\nelement vertex " + std::to_string(mesh.positions.size()) +
              "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
              std::to_string(mesh.faces.size()) + "\nproperty list " + (wide ? "int" : "uchar") +
              " int vertex_indices\n";
    if (uvs) header += std::string("property list ") + (wide ? "int" : "uchar") + " float texcoord\n";
    header += "end_header\n";
    PlyOut out(binary);
    out.text() = header;
    for (const auto& p : mesh.positions) {
        for (double x : p) out.value(x);
        out.end_instance();
    }
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const auto& f = mesh.faces[i];
        const auto count = [&](std::size_t n) {
            if (wide)
                out.value(static_cast<std::int32_t>(n));
            else if (binary)
                out.value(static_cast<std::uint8_t>(n));
            else
                out.value(static_cast<int>(n)); // to_chars of a char type would not be a number
        };
        count(f.size());
        for (int v : f) out.value(static_cast<std::int32_t>(v));
        if (uvs) {
            count(2 * mesh.face_uvs[i].size());
            for (const auto& t : mesh.face_uvs[i])
                for (std::int64_t c : t) out.value(static_cast<float>(c));
        }
        out.end_instance();
    }
    const std::string tmp = path + ".tmp";
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (!file) return {IoError::Code::CannotWrite, "cannot write '" + tmp + "'", 0};
    const std::string& bytes = out.text();
    (void)std::fwrite(bytes.data(), 1, bytes.size(), file); // a short write sets the error flag
    return io_detail::close_and_rename(file, tmp, path);
}

} // namespace qex
