// The working mesh made from the input, and its half-edge connectivity, with manifold and
// orientation checks.
#include "pipeline.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

namespace qex::detail {
namespace {

// ============================================================================ opposite half-edges

// Half-edges ordered by undirected edge (smaller vertex, larger vertex), then by index; pairs
// become opposites. Bucketed by the smaller vertex (counting sort); each bucket holds
// (larger vertex) << 32 | half-edge << 1 | direction (1: from the larger vertex) and is
// sorted by insertion: linear time, 8 bytes per half-edge. (Large buckets, at vertices of
// high valence, are sorted by std::sort.) The direction bit decides orientation without
// looking the half-edges up again.

/// The half-edges bucketed by the smaller vertex of their edge, in the entry format above.
struct EdgeBuckets {
    std::vector<int> bucket;          ///< bucket v: entries [bucket[v], bucket[v + 1])
    std::vector<std::uint64_t> entry; ///< per half-edge
};

/// Buckets of more entries than this (vertices of high valence) are sorted by std::sort.
constexpr int kMaxInsertionSort = 32;

/// Per part: how many of its half-edges each vertex is the smaller vertex of.
std::vector<std::vector<int>> count_smaller_vertices(const TriMesh& m, int parts) {
    const int nh = 3 * m.num_faces();
    std::vector<std::vector<int>> count(static_cast<std::size_t>(parts));
    for_parts(parts, parts, nh, [&](int part, std::int64_t begin, std::int64_t end) {
        std::vector<int>& c = count[static_cast<std::size_t>(part)];
        c.assign(static_cast<std::size_t>(m.num_vertices), 0); // on the thread that fills it
        for (auto h = static_cast<int>(begin); h < end; ++h)
            ++c[static_cast<std::size_t>(std::min(m.origin(h), m.target(h)))];
    });
    return count;
}

/// Turns count[part][v] into where part's entries of bucket v start; sets the bucket bounds.
void bucket_offsets(std::vector<std::vector<int>>& count, int nv, std::vector<int>& bucket) {
    const int parts = static_cast<int>(count.size());
    int at = 0;
    for (int v = 0; v < nv; ++v) {
        bucket[v] = at;
        for (int part = 0; part < parts; ++part) {
            int& c = count[static_cast<std::size_t>(part)][static_cast<std::size_t>(v)];
            const int n = c;
            c = at;
            at += n;
        }
    }
    bucket[nv] = at;
}

/// Writes every half-edge's entry at its part's next place in its bucket (`fill_at`: per part, from
/// bucket_offsets).
void place_entries(const TriMesh& m, std::vector<std::vector<int>>& fill_at, std::vector<std::uint64_t>& entry) {
    const int nh = 3 * m.num_faces();
    const int parts = static_cast<int>(fill_at.size());
    for_parts(parts, parts, nh, [&](int part, std::int64_t begin, std::int64_t end) {
        std::vector<int>& fill = fill_at[static_cast<std::size_t>(part)];
        for (auto h = static_cast<int>(begin); h < end; ++h) {
            const int a = m.origin(h), b = m.target(h);
            entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(std::min(a, b))]++)] =
                static_cast<std::uint64_t>(std::max(a, b)) << 32 | static_cast<std::uint32_t>(h) << 1 |
                (a > b ? 1u : 0u);
        }
    });
}

/// Counting sort by the smaller vertex. With several threads, each counts and places one
/// contiguous range of half-edges with its own counters, ranges in order: entries land exactly
/// where a serial pass would put them. Buckets are not sorted yet.
EdgeBuckets bucket_half_edges(const TriMesh& m) {
    const int nh = 3 * m.num_faces();
    EdgeBuckets b;
    b.bucket.assign(static_cast<std::size_t>(m.num_vertices) + 1, 0);
    b.entry.resize(static_cast<std::size_t>(nh));
    const int parts = m.parts(nh);
    std::vector<std::vector<int>> count = count_smaller_vertices(m, parts);
    bucket_offsets(count, m.num_vertices, b.bucket);
    place_entries(m, count, b.entry);
    return b;
}

/// Sorts entries [lo, hi): by insertion, or by std::sort for a large bucket.
void sort_bucket(std::vector<std::uint64_t>& entry, int lo, int hi) {
    if (hi - lo > kMaxInsertionSort) { // a vertex of high valence: no quadratic sort
        std::sort(entry.begin() + lo, entry.begin() + hi);
    } else {
        for (int i = lo + 1; i < hi; ++i)
            for (int j = i; j > lo && entry[j] < entry[j - 1]; --j) std::swap(entry[j], entry[j - 1]);
    }
}

/// The error for the edge of half-edge h: `n` incident triangles (non-manifold), or h and o
/// traversing it in the same direction.
Error edge_error(const TriMesh& m, int h, int o, int n, bool non_manifold, const char* what) {
    const std::string edge = "edge (" + std::to_string(m.input_vertex[m.origin(h)]) + ", " +
                             std::to_string(m.input_vertex[m.target(h)]) + ")";
    return non_manifold ? Error{ErrorCode::NonManifoldEdge,
                                edge + " has " + std::to_string(n) + " incident triangles (" + what + ")",
                                m.input_triangle[TriMesh::face(h)]}
                        : Error{ErrorCode::InconsistentOrientation,
                                edge + ": triangles " + std::to_string(m.input_triangle[TriMesh::face(h)]) + " and " +
                                    std::to_string(m.input_triangle[TriMesh::face(o)]) +
                                    " traverse it in the same direction (" + what + ")",
                                m.input_triangle[TriMesh::face(o)]};
}

/// Pairs the runs of equal larger vertex in sorted bucket v into opposites. Returns whether the
/// bucket has an edge with more than two half-edges or two of the same direction (described in
/// `*error` if given); pairing stops there.
bool pair_bucket(TriMesh& m, const EdgeBuckets& b, int v, const char* what, Error* error) {
    const std::vector<std::uint64_t>& entry = b.entry;
    for (int i = b.bucket[v]; i < b.bucket[v + 1];) {
        int j = i + 1;
        while (j < b.bucket[v + 1] && entry[j] >> 32 == entry[i] >> 32) ++j;
        const auto h = static_cast<int>((entry[i] & 0xffffffffu) >> 1);
        const auto o = j - i == 2 ? static_cast<int>((entry[i + 1] & 0xffffffffu) >> 1) : -1;
        const bool non_manifold = j - i > 2, misoriented = o >= 0 && (entry[i] & 1) == (entry[i + 1] & 1);
        if ((non_manifold || misoriented) && error) *error = edge_error(m, h, o, j - i, non_manifold, what);
        if (non_manifold || misoriented) return true;
        if (o >= 0) m.opp[h] = o, m.opp[o] = h;
        i = j;
    }
    return false;
}

/// Per bucket: sort, then pair into opposites (m.opp). A bucket with a problem only marks
/// itself; the first such bucket is reported, as a serial scan would.
Error pair_opposites(TriMesh& m, EdgeBuckets& b, const char* what) {
    const int nv = m.num_vertices;
    m.opp.assign(3 * m.num_faces(), -1);
    const int parts = m.parts(3 * m.num_faces());
    std::vector<int> bad(static_cast<std::size_t>(parts), nv); // per part, its first bad bucket
    for_parts(parts, parts, nv, [&](int part, std::int64_t begin, std::int64_t end) {
        for (auto v = static_cast<int>(begin); v < end; ++v) {
            sort_bucket(b.entry, b.bucket[v], b.bucket[v + 1]);
            if (pair_bucket(m, b, v, what, nullptr)) {
                bad[static_cast<std::size_t>(part)] = v;
                break;
            }
        }
    });
    const int first_bad = *std::min_element(bad.begin(), bad.end());
    if (first_bad < nv) {
        Error error;
        pair_bucket(m, b, first_bad, what, &error);
        return error;
    }
    return {};
}

// ============================================================================ fans

/// Fan sizes, boundary flags and fan starts: the start of a boundary vertex's fan is its most
/// counter-clockwise corner, of an interior vertex its first corner. Fails at a vertex with
/// several boundary fans.
Error build_fans(TriMesh& m, const char* what) {
    const int nv = m.num_vertices, nh = 3 * m.num_faces();
    m.fan_start.assign(nv, -1);
    m.fan_size.assign(nv, 0);
    m.on_boundary.assign(nv, 0);
    for (int h = 0; h < nh; ++h) {
        const int v = m.origin(h);
        ++m.fan_size[v];
        if (m.opp[TriMesh::prev(h)] < 0) {
            if (m.on_boundary[v])
                return {ErrorCode::NonManifoldVertex,
                        "vertex " + std::to_string(m.input_vertex[v]) + " has several boundary fans (" + what + ")",
                        m.input_vertex[v]};
            m.on_boundary[v] = 1;
            m.fan_start[v] = h;
        } else if (m.fan_start[v] < 0) {
            m.fan_start[v] = h;
        }
    }
    return {};
}

/// TriMesh::vertex_order: referenced vertices in the order their first corners appear.
void list_vertex_order(TriMesh& m) {
    const int nv = m.num_vertices, nh = 3 * m.num_faces();
    m.vertex_order.clear();
    m.vertex_order.reserve(static_cast<std::size_t>(nv));
    std::vector<char> listed(static_cast<std::size_t>(nv), 0);
    for (int h = 0; h < nh; ++h)
        if (!listed[m.origin(h)]) listed[m.origin(h)] = 1, m.vertex_order.push_back(m.origin(h));
}

/// Each fan must hold all of its vertex's corners; the first vertex (in vertex_order) whose
/// fan does not is reported.
Error check_single_fans(const TriMesh& m, const char* what) {
    const auto listed = static_cast<std::int64_t>(m.vertex_order.size());
    const int parts = m.parts(3 * m.num_faces());
    std::vector<std::int64_t> split(static_cast<std::size_t>(parts), listed); // per part, its first split fan
    for_parts(parts, parts, listed, [&](int part, std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
            const int v = m.vertex_order[static_cast<std::size_t>(i)];
            int count = 0;
            for (int h = m.fan_start[v]; h >= 0;) {
                ++count;
                h = m.cw(h);
                if (h == m.fan_start[v] || count > m.fan_size[v]) break;
            }
            if (count != m.fan_size[v]) {
                split[static_cast<std::size_t>(part)] = i;
                break;
            }
        }
    });
    const std::int64_t first_split = *std::min_element(split.begin(), split.end());
    if (first_split < listed) {
        const int v = m.vertex_order[static_cast<std::size_t>(first_split)];
        return {ErrorCode::NonManifoldVertex,
                "the triangles around vertex " + std::to_string(m.input_vertex[v]) + " do not form a single fan (" +
                    what + ")",
                m.input_vertex[v]};
    }
    return {};
}

} // namespace

TriMesh make_mesh(const Input& in) {
    TriMesh m;
    m.num_vertices = static_cast<int>(in.positions.size());
    m.tri = in.triangles;
    m.uv = in.uvs;
    m.positions = &in.positions;
    m.corner_vertex.resize(3 * in.triangles.size());
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) m.corner_vertex[3 * f + k] = in.triangles[f][k];
    m.input_triangle.resize(in.triangles.size());
    std::iota(m.input_triangle.begin(), m.input_triangle.end(), 0);
    m.input_vertex.resize(in.positions.size());
    std::iota(m.input_vertex.begin(), m.input_vertex.end(), 0);
    return m;
}

Error build_topology(TriMesh& m, const char* what) {
    {
        EdgeBuckets buckets = bucket_half_edges(m);
        if (Error e = pair_opposites(m, buckets, what); e.code != ErrorCode::None) return e;
    } // the buckets are freed before the fans are built
    if (Error e = build_fans(m, what); e.code != ErrorCode::None) return e;
    list_vertex_order(m);
    return check_single_fans(m, what);
}

} // namespace qex::detail
