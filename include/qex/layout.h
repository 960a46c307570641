// The quad layout of a quad mesh: the separatrices (grid lines along mesh edges from its special
// vertices) and the rectangular patches they cut the mesh into, with each patch's integer size and
// its neighbours. For spline fitting and CAD (issue 33). The layout sees only the mesh's faces (and
// positions, for canonical orders): any quad mesh works, qex's own output or another's. Every
// layout is judged by an independent check (check_layout) before it is returned as valid.
// Never throws (std::bad_alloc aside), never prints.
#pragma once

#include "qex/mesh.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace qex {

/// Where a separatrix starts.
enum class SeparatrixStart : std::uint8_t {
    IrregularVertex, ///< an interior vertex of valence other than 4
    BoundaryVertex,  ///< a boundary vertex whose fan between two boundary edges is not 2 faces
    FeatureVertex,   ///< a vertex on a feature line whose fan between two feature edges is not 2 faces
    /// A cut, from a regular vertex of a patch's side across the patch, where the separatrices
    /// leave a patch that is not a rectangle embedded in the mesh: an annulus between two boundary
    /// loops without corners (cut twice, from its first boundary vertex in the canonical order and
    /// half way round that loop), or a rectangle glued to itself along a separatrix (cut from the
    /// middle of a free side, parallel to the glued ones).
    Cut,
};
const char* to_string(SeparatrixStart start);

/// How a separatrix ends (the motorcycle-graph rules: all are traced at once, one edge per step).
enum class SeparatrixEnd : std::uint8_t {
    SpecialVertex, ///< at a special vertex (irregular, boundary corner, feature corner)
    Boundary,      ///< at a regular vertex of the boundary
    Feature,       ///< at a regular vertex of a feature line
    /// At a vertex another separatrix (or its own earlier path) passed through first: a
    /// T-junction. This also ends a grid line that would loop round the surface without end.
    Separatrix,
    /// It met a separatrix traced from the other end along the same grid line: the two are joined
    /// into this one, which runs from special vertex to special vertex.
    HeadOn,
};
const char* to_string(SeparatrixEnd end);

struct Separatrix {
    /// Mesh vertices from its start to its end, each two consecutive joined by a mesh edge.
    std::vector<int> vertices;
    SeparatrixStart start = SeparatrixStart::IrregularVertex;
    SeparatrixEnd end = SeparatrixEnd::SpecialVertex;
};

enum class PatchKind : std::uint8_t {
    Rectangle, ///< a disk whose boundary has 4 corners: a u x v grid of faces
    /// A whole closed component without special vertex (a torus): no separatrix cuts it; u is the
    /// length of its grid lines in one direction, v = faces / u.
    Torus,
};
const char* to_string(PatchKind kind);

struct Patch {
    PatchKind kind = PatchKind::Rectangle;
    /// Faces of the patch (u * v of them), in increasing order.
    std::vector<int> faces;
    /// Its size in faces: u along the side from corners[0] to corners[1], v along the next.
    int u = 0, v = 0;
    /// Rectangle: its corner vertices, counter-clockwise, starting at the first in the canonical
    /// vertex order. Torus: {-1, -1, -1, -1}.
    std::array<int, 4> corners{-1, -1, -1, -1};
};

/// Two patches sharing mesh edges (a < b), and how many.
struct PatchAdjacency {
    int a = -1, b = -1;
    int shared_edges = 0;
};

struct Layout {
    /// True when the check (check_layout) accepted the layout; false with the reason in `error`
    /// (a mesh that is not an oriented manifold all-quad mesh, or a layout the check rejects).
    bool valid = false;
    std::string error;
    /// Special vertices (irregular, boundary corners, feature corners), increasing.
    std::vector<int> special_vertices;
    /// In canonical order: by their first vertex, then their second, in the vertex order below.
    std::vector<Separatrix> separatrices;
    /// The patch of each face.
    std::vector<int> face_patch;
    /// In canonical order (by their first face in the vertex order below).
    std::vector<Patch> patches;
    /// Sorted by (a, b).
    std::vector<PatchAdjacency> adjacency;
    /// Anything worth saying in words (a torus without separatrix, a patch cut).
    std::vector<std::string> notes;
};

struct LayoutOptions {
    /// Feature edges of the quad mesh (vertex pairs, each an edge of the mesh): cut like the
    /// boundary; their corners are special vertices.
    std::vector<std::array<int, 2>> feature_edges;
};

/// The quad layout of `mesh` (all faces quads, an oriented 2-manifold). Canonical: the same for
/// any order of the faces, of their corners and of the vertices (up to the renumbering), as long
/// as vertices have distinct positions (ties fall back to indices). Serial, so independent of any
/// thread count. Never returns a layout as valid that check_layout rejects.
Layout extract_layout(const QuadMesh& mesh, const LayoutOptions& options = {});

/// The independent check of a layout (its own code: none of the tracing is shared): the patches
/// cover the mesh, each is a disk whose boundary has exactly 4 corners and runs along separatrices,
/// boundary or feature edges, with only regular vertices inside and u * v faces, sides of u and v
/// edges (a Torus patch: a whole closed component without special vertex); the separatrices run
/// along mesh edges, straight through regular vertices, from a special vertex to where their end
/// says; the adjacency is the patches' shared edges. Returns the first problem found, or "".
std::string check_layout(const QuadMesh& mesh, const Layout& layout, const LayoutOptions& options = {});

/// The edges of qex's mesh (with its provenance) that run along the input's feature edges
/// (Input::feature_edges, snapped onto iso-lines by the extraction): both ends on one feature
/// edge, at one of its vertices or inside it. For LayoutOptions::feature_edges. Empty for a mesh
/// without provenance.
std::vector<std::array<int, 2>> quad_feature_edges(const Input& input, const QuadMesh& mesh);

/// The layout as JSON: "valid", "error", "special_vertices", "separatrices" (vertices, start,
/// end), "patches" (kind, u, v, corners, faces), "face_patch", "adjacency", "notes".
std::string layout_json(const Layout& layout, int indent = 2);

} // namespace qex
