// Internal data of the extraction pipeline and the stages that fill it, in the order they run.
// Each stage lives in its own file, named for what it does.
#pragma once

#include "grid_automorphism.h"
#include "predicates.h"
#include "thread_count.h"
#include "qex/qex.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace qex::detail {

// ============================================================================ triangle mesh

/// Transitions per half-edge, 16 bytes each instead of GridAutomorphism's 24: the rotation sits
/// in the two low bits of 4 * tx. Exact while |tx| < 2^61; transitions between charts of a map
/// whose values are below 2^52 (input validation) stay below 2^54.
class TransitionTable {
public:
    /// n entries, not initialised: the caller writes every one (compute_transitions does).
    void allocate(std::size_t n) {
        if (n != size_) data_.reset(new Packed[n]);
        size_ = n;
    }
    std::size_t size() const { return size_; }
    GridAutomorphism operator[](std::size_t h) const {
        const Packed& p = data_[h];
        return {static_cast<int>(p.tx_r & 3), p.tx_r >> 2, p.ty};
    }
    void set(std::size_t h, const GridAutomorphism& g) {
        // 4 * tx as an unsigned product: no signed overflow, and exact in the stated range.
        const auto scaled = static_cast<std::int64_t>(static_cast<std::uint64_t>(g.tx) << 2);
        data_[h] = {scaled | (g.r & 3), g.ty};
    }

private:
    struct Packed {
        std::int64_t tx_r; ///< 4 * tx + r
        std::int64_t ty;
    };
    std::unique_ptr<Packed[]> data_;
    std::size_t size_ = 0;
};

/// Corner-based triangle mesh. Corner h = 3f + k is vertex tri[f][k] in triangle f, and also the
/// half-edge from that vertex to tri[f][(k+1)%3].
struct TriMesh {
    int num_vertices = 0;
    std::vector<std::array<int, 3>> tri;
    std::vector<Point2> uv;                        ///< per corner, in the chart of its triangle
    /// Per corner: the input vertex whose 3D position the corner keeps (survives collapses).
    std::vector<int> corner_vertex;
    const std::vector<std::array<double, 3>>* positions = nullptr; ///< the input's, outlives the mesh
    const std::array<double, 3>& pos(int c) const { return (*positions)[static_cast<std::size_t>(corner_vertex[c])]; }
    std::vector<int> input_triangle;               ///< per triangle: index in the input
    std::vector<int> input_vertex;                 ///< per vertex: a representative input vertex

    // connectivity (build_topology)
    std::vector<int> opp;           ///< per half-edge: opposite half-edge, -1 on the boundary
    std::vector<int> fan_start;     ///< per vertex: first corner of its fan in clockwise order
    std::vector<int> fan_size;      ///< per vertex: number of corners
    std::vector<char> on_boundary;  ///< per vertex
    /// Referenced vertices in the order their first corners appear. Walking fans in this order
    /// keeps consecutive fans in nearby memory (vertex numbering often has no locality at all).
    std::vector<int> vertex_order;
    /// Threads for the parallel loops (Options::threads; 1 = serial). Results do not depend on it.
    int threads = 1;
    /// Whether a loop over `n` elements runs in parallel: small meshes stay serial, where
    /// starting threads costs more than it saves.
    bool parallel(std::int64_t n) const { return threads > 1 && n >= (1 << 16); }

    // map (transitions, sanitization, valences)
    TransitionTable transition; ///< per half-edge h: chart of face(h) -> chart of face(opp h)
    std::vector<signed char> face_sign;       ///< per triangle: sign of its UV area (exact)
    std::vector<int> valence;                 ///< per vertex: valence (Algorithm 8 or given)
    std::vector<int> winding_valence;         ///< per vertex: signed angle sum / (pi/2), rounded
    std::vector<char> singular;               ///< per vertex

    int num_faces() const { return static_cast<int>(tri.size()); }
    static int face(int h) { return h / 3; }
    static int next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
    static int prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }
    int origin(int h) const { return tri[h / 3][h % 3]; }
    int target(int h) const { return origin(next(h)); }
    /// Next corner clockwise around the origin of h (across the edge h), or -1 at the boundary.
    int cw(int h) const { return opp[h] < 0 ? -1 : next(opp[h]); }
    /// Next corner counter-clockwise around the origin of h (across the edge prev(h)), or -1.
    int ccw(int h) const { return opp[prev(h)]; }
};

// ============================================================================ stages


/// The working mesh of an input whose values are valid (validate_input_values).
TriMesh make_mesh(const Input& in);

/// Checks indices, finiteness, magnitudes and isolated vertices of the raw input.
Error validate_input_values(const Input& in);

/// Builds opposite half-edges and clockwise vertex fans; rejects non-manifold or misoriented meshes.
/// `what` names the stage in messages ("input" or "after collapsing UV-degenerate edges").
Error build_topology(TriMesh& m, const char* what);

/// Collapses edges of zero length in the parameter domain, keeping 3D positions in the corners.
/// Returns the number collapsed in `collapsed`.
Error collapse_degenerate_edges(TriMesh& m, std::int64_t& collapsed);

/// Extracts and rounds a transition function per interior half-edge (Section 3.1).
void compute_transitions(TriMesh& m);

/// The angle atan2(y, x) for y >= 0, within kApproximateAngleError of it (a polynomial, no
/// libm call); NaN when x and y are both 0 or not finite.
double approximate_angle(double y, double x);
/// A bound on |approximate_angle - atan2|, with a margin of 10 over the polynomial's 1e-5 (the
/// unit test samples the whole range).
inline constexpr double kApproximateAngleError = 1e-4;

/// Valence counting robust to fold-overs (Algorithm 8) and winding valences; interior vertices
/// only. Vertices not counted (boundary, or regular when `singular_only`) get 4.
void count_valences(TriMesh& m, bool singular_only = false);

/// Fallback: relaxes regular vertices within `rings` of a flipped triangle towards the average of
/// their neighbours, through exact transitions. Returns the number of triangles still flipped.
std::int64_t untangle_fold_overs(TriMesh& m, int rings, int iterations);

/// For a mesh extracted from a relaxed map: moves every output vertex onto a preimage of its grid
/// point in `given` (the sanitized map as given, per input corner, NaN where collapsed), found
/// by a breadth-first search from its provenance triangle, and sets its provenance and the
/// mesh's map to that map. Returns the number of vertices it could not place.
std::int64_t place_on_given_map(const Input& input, const std::vector<std::array<double, 2>>& given, QuadMesh& mesh);

/// Precision truncation, singularity snapping and propagation (Algorithms 1 and 2); feature
/// snapping (Section 3.2). `given_valences` may be empty.
/// Branch points (r = 0, valence 8 or more) are snapped only when `branch_points` is set; with
/// it unset they are truncated like regular vertices and counted in `*deferred`. (Their
/// valence comes from angles, which noise makes meaningless next to an edge that is about to
/// become degenerate: the caller decides them once such edges are collapsed.)
Error sanitize(TriMesh& m, const std::vector<int>& given_valences,
               const std::vector<std::array<int, 2>>& feature_edges, Report& report, bool branch_points = true,
               std::int64_t* deferred = nullptr);

// ============================================================================ q-vertices and q-ports

struct QVertex {
    QVertexKind kind;
    int element;       ///< vertex id (Vertex), canonical half-edge (Edge), triangle (Face)
    int chart;         ///< triangle whose chart `grid` is expressed in
    IPoint grid;       ///< integer parameter position in that chart
    std::array<double, 3> position;
    std::array<double, 3> barycentric; ///< in triangle `chart` (corner order)
    int first_port = 0, num_ports = 0;
};

/// An outgoing unconnected q-edge: q-vertex, triangle it points into, direction (R90^dir (1,0) in
/// that triangle's chart) and the q-vertex's grid point in that chart.
struct Port {
    int qvertex;
    int corner;   ///< corner of the triangle at the q-vertex's fan position (Vertex); triangle*3 otherwise
    int dir;
    IPoint grid;
};

/// A traced iso-line from one port to another; `g` maps the chart of the source port's triangle
/// to the chart of the target port's triangle.
struct Connection {
    int to = -1;          ///< target port, -1 if dangling (boundary) or failed
    GridAutomorphism g;
};

struct QState {
    std::vector<QVertex> qvertices;
    std::vector<int> vertex_qvertex;   ///< per mesh vertex: its vertex-q-vertex or -1
    /// Edge-q-vertices of half-edge h: [edge_first[h], edge_first[h + 1]) (empty unless h is its
    /// edge's smaller half-edge); size 3F + 1.
    std::vector<int> edge_first;
    /// Face-q-vertices of triangle f: [face_first[f], face_first[f + 1]); size F + 1.
    std::vector<int> face_first;
    std::vector<Port> ports;
    std::vector<Connection> connections;     ///< per port
    std::vector<char> dangling;              ///< per port: trace left the surface through a boundary
};

/// Generates vertex-, edge- and face-q-vertices (Algorithm 3).
Error generate_qvertices(const TriMesh& m, const Options& opt, QState& q);

/// Enumerates q-ports of every q-vertex in clockwise order on the surface (Algorithm 4).
void enumerate_ports(const TriMesh& m, QState& q);

/// Traces every port's iso-line to its opposite port (Algorithm 5).
void trace_ports(const TriMesh& m, const Options& opt, QState& q, Report& report);

// ============================================================================ faces

/// The closed face walks, stored flat (one allocation for all of them, not two per face):
/// walk i is corners [first[i], first[i + 1]) of `qv` and `uv`.
struct FaceWalks {
    std::vector<std::size_t> first{0};
    std::vector<int> qv;    ///< q-vertices
    std::vector<IPoint> uv; ///< local UVs in the chart of the walk's first port's triangle
    std::size_t size() const { return first.size() - 1; }
};

/// Walks the faces of the q-port graph, accumulating local UVs (Algorithm 6).
FaceWalks extract_faces(const TriMesh& m, const QState& q, Report& report);

/// Transition from the chart of port a's triangle to that of port b (same q-vertex), stepping
/// clockwise around the q-vertex; `ok` is false if the step would cross the mesh boundary.
GridAutomorphism fan_transition_cw(const TriMesh& m, const QState& q, int a, int b, bool& ok);

/// Recovers lost q-edges (Section 5.5), merges q-vertex clones (Algorithm 7) and simplifies faces;
/// fills the output mesh. Of `q` it reads only the q-vertices (the driver releases the ports and
/// traces before calling it).
void merge_and_simplify(const TriMesh& m, const QState& q, FaceWalks faces,
                        const Options& opt, QuadMesh& out, Report& report);

} // namespace qex::detail
