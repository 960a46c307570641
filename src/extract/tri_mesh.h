// The extractor's working mesh: corner-based connectivity (built once from the input, rebuilt by
// every collapse), the corner data it carries (UVs, 3D positions, input numbering), and the map
// state derived from both, which a collapse invalidates.
#pragma once

#include "grid_automorphism.h"
#include "parallel.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace qex::detail {

/// The indices i < n where a[i] and b[i] differ as bytes, in order: blocks of entries compared
/// whole first (most of two copies of a map are the same).
template <class T>
std::vector<std::size_t> differing_entries(const T* a, const T* b, std::size_t n) {
    constexpr std::size_t kBlock = 256;
    std::vector<std::size_t> out;
    for (std::size_t lo = 0; lo < n; lo += kBlock) {
        const std::size_t hi = std::min(n, lo + kBlock);
        if (std::memcmp(a + lo, b + lo, (hi - lo) * sizeof(T)) == 0) continue;
        for (std::size_t i = lo; i < hi; ++i)
            if (std::memcmp(a + i, b + i, sizeof(T)) != 0) out.push_back(i);
    }
    return out;
}

/// Transitions per half-edge, 16 bytes each instead of GridAutomorphism's 24: the rotation sits
/// in the two low bits of 4 * tx. Exact while |tx| < 2^61; transitions between charts of a map
/// whose values are below 2^52 (input validation) stay below 2^54.
class TransitionTable {
public:
    TransitionTable() = default;
    TransitionTable(TransitionTable&&) noexcept = default;
    TransitionTable& operator=(TransitionTable&&) noexcept = default;
    /// A deep copy (the ladder's later rungs each start from a copy of the prepared mesh).
    TransitionTable(const TransitionTable& other) { *this = other; }
    TransitionTable& operator=(const TransitionTable& other) {
        if (this == &other) return *this;
        // The same size: the buffer is reused (RetryBeside copies a map's transitions often).
        if (size_ != other.size_) data_.reset(other.size_ > 0 ? new Packed[other.size_] : nullptr);
        size_ = other.size_;
        std::copy(other.data_.get(), other.data_.get() + size_, data_.get());
        return *this;
    }
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
    /// The half-edges whose transitions differ from `other`'s (of the same size), in order:
    /// compared a block at a time, as bytes (each transition has one packed form).
    std::vector<std::size_t> differing(const TransitionTable& other) const {
        return differing_entries(data_.get(), other.data_.get(), size_);
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

/// Per-element facts of the map, derived from a TriMesh's connectivity and UVs (transitions,
/// valences, sanitization): valid only for the connectivity they were computed on.
struct MapState {
    TransitionTable transition;         ///< per half-edge h: chart of face(h) -> chart of face(opp h)
    std::vector<signed char> face_sign; ///< per triangle: sign of its UV area (exact)
    std::vector<int> valence;           ///< per vertex: valence (Algorithm 8 or given)
    std::vector<int> winding_valence;   ///< per vertex: signed angle sum / (pi/2), rounded
    std::vector<char> singular;         ///< per vertex
    /// Whether every array is sized for a mesh of `faces` triangles and `vertices` vertices.
    bool sized_for(int faces, int vertices) const {
        const auto f = static_cast<std::size_t>(faces), v = static_cast<std::size_t>(vertices);
        return transition.size() == 3 * f && face_sign.size() == f && valence.size() == v &&
               winding_valence.size() == v && singular.size() == v;
    }
};

/// Corner-based triangle mesh. Corner h = 3f + k is vertex tri[f][k] in triangle f, and also the
/// half-edge from that vertex to tri[f][(k+1)%3].
struct TriMesh {
    int num_vertices = 0;
    std::vector<std::array<int, 3>> tri;
    std::vector<Point2> uv; ///< per corner, in the chart of its triangle
    /// Per corner: the input vertex whose 3D position the corner keeps (survives collapses).
    std::vector<int> corner_vertex;
    const std::vector<std::array<double, 3>>* positions = nullptr; ///< the input's, outlives the mesh
    const std::array<double, 3>& pos(int c) const { return (*positions)[static_cast<std::size_t>(corner_vertex[c])]; }
    std::vector<int> input_triangle; ///< per triangle: index in the input
    std::vector<int> input_vertex;   ///< per vertex: a representative input vertex
    /// Vertex v's 3D position: its representative input vertex's.
    const std::array<double, 3>& vertex_pos(int v) const {
        return (*positions)[static_cast<std::size_t>(input_vertex[static_cast<std::size_t>(v)])];
    }

    // connectivity (build_topology)
    std::vector<int> opp;          ///< per half-edge: opposite half-edge, -1 on the boundary
    std::vector<int> fan_start;    ///< per vertex: first corner of its fan in clockwise order
    std::vector<int> fan_size;     ///< per vertex: number of corners
    std::vector<char> on_boundary; ///< per vertex
    /// Referenced vertices in the order their first corners appear. Walking fans in this order
    /// keeps consecutive fans in nearby memory (vertex numbering often has no locality at all).
    std::vector<int> vertex_order;
    /// Threads for the parallel loops (Options::threads; 1 = serial). Results do not depend on it.
    int threads = 1;
    /// The factor a refinement multiplied the map by (1: the map as given): its solver noise is
    /// multiplied with it (solver_noise_bound).
    double noise_scale = 1.0;
    /// Whether a loop over `n` elements runs in parallel.
    bool parallel(std::int64_t n) const { return run_parallel(threads, n); }
    /// How many parts a loop over n elements is split into (for_parts).
    int parts(std::int64_t n) const { return parts_for(threads, n); }

    /// What the map says about this connectivity. A collapse builds a new connectivity and
    /// leaves this empty, so it must be computed again before anything reads it.
    MapState map;

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

} // namespace qex::detail
