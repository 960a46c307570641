// Files: the OBJ and PLY maps parametrizers write, VVAL valence files, and quad meshes as OBJ or
// PLY. Every reader reports the first problem with its line (PLY data: its byte offset and
// element) and leaves its output empty; every writer goes through a temporary file renamed into
// place, so no partial file is ever left.
#pragma once

#include "qex/mesh.h"
#include "qex/verify.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace qex {

struct IoError {
    enum class Code {
        None,
        CannotOpen,
        CannotWrite,
        Syntax,
        MissingUv,
        NonTriangle,
        IndexOutOfRange,
        NonFinite,
        VvalSyntax,
        PlySyntax ///< a PLY header or element that cannot be read (the message names it)
    };
    Code code = Code::None;
    std::string message;
    std::int64_t line = 0;    ///< 1-based line number, 0 if not applicable
    std::int64_t offset = -1; ///< PLY: byte offset in the file of the problem, -1 if not applicable
    bool ok() const { return code == Code::None; }
};

/// Parses an OBJ with `v`, `vt` and `f a/ta b/tb c/tc` records (one UV per face corner).
/// `threads` parse large inputs in pieces (0: every core, 1: serial); the result, and the first
/// problem reported with its line, are those of a serial read. On a problem `out` is left empty.
IoError parse_obj(const char* data, std::size_t size, Input& out, int threads = 0);
IoError read_obj(const std::string& path, Input& out, int threads = 0);
/// Reads a VVAL valence file: `{"file_format":"VVAL","version":1}`, vertex count, one integer each.
IoError read_vval(const std::string& path, std::vector<int>& valences);
IoError parse_vval(const char* data, std::size_t size, std::vector<int>& valences);
/// Writes the quad mesh as OBJ (local UVs as `vt`), through a temporary file renamed into place.
/// With `threads` other than 1 (0: when the machine has several cores) a large mesh's text is
/// written out on a second thread while the next block is formatted; the file is the same.
/// Memory stays bounded by the blocks, however many corners a face has.
IoError write_obj(const std::string& path, const QuadMesh& mesh, int threads = 0);
/// Reads a polygon OBJ (v and f records; vt ignored) as a QuadMesh without UVs or provenance.
IoError read_polygon_obj(const std::string& path, QuadMesh& out);

/// Parses a PLY map (ASCII, binary little or big endian): `vertex` with x, y, z; `face` with a
/// `vertex_indices` (or `vertex_index`) list of 3 and a `texcoord` list of 6 (u, v per corner,
/// the MeshLab/Blender convention), or per-vertex UVs (s/t, u/v or texture_u/texture_v). Other
/// elements and properties are skipped. A problem in the data names its byte offset and element.
IoError parse_ply(const char* data, std::size_t size, Input& out);
IoError read_ply(const std::string& path, Input& out);
/// Reads a polygon PLY (vertex x, y, z and face vertex lists; UVs ignored) as a QuadMesh.
IoError parse_polygon_ply(const char* data, std::size_t size, QuadMesh& out);
IoError read_polygon_ply(const std::string& path, QuadMesh& out);
/// Writes the quad mesh as PLY (binary little endian, or ASCII): positions as doubles, faces as
/// vertex lists and local UVs as a per-face `texcoord` list, through a temporary file.
IoError write_ply(const std::string& path, const QuadMesh& mesh, bool binary = true);

/// Writes qex's certificate (qex::Certificate; qex::make_certificate gives a result's) as an OBJ
/// map with every digit: a header of comments (`# qex certificate 1`, `# grid_scale K`,
/// `# repaired N`, then `# r` lines of up to 16 triangle indices), then `v`, one `vt` per
/// corner and `f`; through a temporary file renamed into place.
IoError write_certificate(const std::string& path, const Certificate& certificate);
/// Reads a certificate write_certificate wrote: the header strictly (the first line names the
/// format and version, then the grid scale, the count and exactly that many triangle indices,
/// whole numbers in range; a problem names its line), then the map as parse_obj reads it.
IoError parse_certificate(const char* data, std::size_t size, Certificate& out);
IoError read_certificate(const std::string& path, Certificate& out);

} // namespace qex
