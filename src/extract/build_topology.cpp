// Half-edge connectivity of the corner-based triangle mesh, with manifold and orientation checks.
#include "pipeline.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace qex::detail {

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
    const int nf = m.num_faces();
    const int nh = 3 * nf;
    // Half-edges ordered by undirected edge (smaller vertex, larger vertex), then by index; pairs
    // become opposites. Bucketed by the smaller vertex (counting sort); each bucket holds
    // (larger vertex) << 32 | half-edge << 1 | direction (1: from the larger vertex) and is
    // sorted by insertion: linear time, 8 bytes per half-edge. (Large buckets, at vertices of
    // high valence, are sorted by std::sort.) The direction bit decides orientation without
    // looking the half-edges up again.
    const int nv = m.num_vertices;
    std::vector<int> bucket(static_cast<std::size_t>(nv) + 1, 0); // bucket v: [bucket[v], bucket[v+1])
    std::vector<std::uint64_t> entry(static_cast<std::size_t>(nh));
    {
        // Counting sort by the smaller vertex. With several threads, each counts and places one
        // contiguous range of half-edges with its own counters, ranges in order: entries land
        // exactly where a serial pass would put them.
        const int parts = m.parallel(nh) ? std::max(1, m.threads) : 1;
        std::vector<std::vector<int>> count(static_cast<std::size_t>(parts), std::vector<int>(static_cast<std::size_t>(nv), 0));
        auto range = [&](int part) { return std::pair<int, int>(static_cast<int>(static_cast<std::int64_t>(nh) * part / parts),
                                                                 static_cast<int>(static_cast<std::int64_t>(nh) * (part + 1) / parts)); };
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
#endif
        for (int part = 0; part < parts; ++part) {
            std::vector<int>& c = count[static_cast<std::size_t>(part)];
            for (int h = range(part).first; h < range(part).second; ++h) ++c[static_cast<std::size_t>(std::min(m.origin(h), m.target(h)))];
        }
        // count[part][v] becomes where part's entries of bucket v start.
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
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
#endif
        for (int part = 0; part < parts; ++part) {
            std::vector<int>& fill = count[static_cast<std::size_t>(part)];
            for (int h = range(part).first; h < range(part).second; ++h) {
                const int a = m.origin(h), b = m.target(h);
                entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(std::min(a, b))]++)] =
                    static_cast<std::uint64_t>(std::max(a, b)) << 32 | static_cast<std::uint32_t>(h) << 1 | (a > b ? 1u : 0u);
            }
        }
    }
    // Per bucket: sort, then pair runs of equal larger vertex into opposites. A bucket with a
    // problem only marks itself; the first such bucket is reported below, as a serial scan would.
    m.opp.assign(nh, -1);
    auto problem = [&](int v, Error* error) {
        for (int i = bucket[v]; i < bucket[v + 1];) {
            int j = i + 1;
            while (j < bucket[v + 1] && entry[j] >> 32 == entry[i] >> 32) ++j;
            const auto h = static_cast<int>((entry[i] & 0xffffffffu) >> 1);
            const auto o = j - i == 2 ? static_cast<int>((entry[i + 1] & 0xffffffffu) >> 1) : -1;
            const bool non_manifold = j - i > 2, misoriented = o >= 0 && (entry[i] & 1) == (entry[i + 1] & 1);
            if ((non_manifold || misoriented) && error) {
                const std::string edge = "edge (" + std::to_string(m.input_vertex[m.origin(h)]) + ", " +
                                         std::to_string(m.input_vertex[m.target(h)]) + ")";
                *error = non_manifold
                             ? Error{ErrorCode::NonManifoldEdge,
                                     edge + " has " + std::to_string(j - i) + " incident triangles (" + what + ")",
                                     m.input_triangle[TriMesh::face(h)]}
                             : Error{ErrorCode::InconsistentOrientation,
                                     edge + ": triangles " + std::to_string(m.input_triangle[TriMesh::face(h)]) + " and " +
                                         std::to_string(m.input_triangle[TriMesh::face(o)]) +
                                         " traverse it in the same direction (" + what + ")",
                                     m.input_triangle[TriMesh::face(o)]};
            }
            if (non_manifold || misoriented) return true;
            if (o >= 0) m.opp[h] = o, m.opp[o] = h;
            i = j;
        }
        return false;
    };
    int first_bad = nv;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(m.threads) if (m.parallel(3 * m.num_faces())) reduction(min : first_bad)
#endif
    for (int v = 0; v < nv; ++v) {
        if (bucket[v + 1] - bucket[v] > 32) { // a vertex of high valence: no quadratic sort
            std::sort(entry.begin() + bucket[v], entry.begin() + bucket[v + 1]);
        } else {
            for (int i = bucket[v] + 1; i < bucket[v + 1]; ++i)
                for (int j = i; j > bucket[v] && entry[j] < entry[j - 1]; --j) std::swap(entry[j], entry[j - 1]);
        }
        if (problem(v, nullptr)) first_bad = std::min(first_bad, v);
    }
    if (first_bad < nv) {
        Error error;
        problem(first_bad, &error);
        return error;
    }
    std::vector<std::uint64_t>().swap(entry);
    // Fans: the start of a boundary vertex's fan is its most counter-clockwise corner.
    m.fan_start.assign(nv, -1);
    m.fan_size.assign(nv, 0);
    m.on_boundary.assign(nv, 0);
    for (int h = 0; h < nh; ++h) {
        const int v = m.origin(h);
        ++m.fan_size[v];
        if (m.opp[TriMesh::prev(h)] < 0) {
            if (m.on_boundary[v])
                return {ErrorCode::NonManifoldVertex,
                        "vertex " + std::to_string(m.input_vertex[v]) +
                            " has several boundary fans (" + what + ")",
                        m.input_vertex[v]};
            m.on_boundary[v] = 1;
            m.fan_start[v] = h;
        } else if (m.fan_start[v] < 0) {
            m.fan_start[v] = h;
        }
    }
    m.vertex_order.clear();
    m.vertex_order.reserve(static_cast<std::size_t>(nv));
    {
        std::vector<char> listed(static_cast<std::size_t>(nv), 0);
        for (int h = 0; h < nh; ++h)
            if (!listed[m.origin(h)]) listed[m.origin(h)] = 1, m.vertex_order.push_back(m.origin(h));
    }
    // Each fan must hold all of its vertex's corners; the first vertex (in vertex_order) whose
    // fan does not is reported.
    const auto listed = static_cast<std::int64_t>(m.vertex_order.size());
    std::int64_t first_split = listed;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(m.threads) if (m.parallel(3 * m.num_faces())) reduction(min : first_split)
#endif
    for (std::int64_t i = 0; i < listed; ++i) {
        const int v = m.vertex_order[static_cast<std::size_t>(i)];
        int count = 0;
        for (int h = m.fan_start[v]; h >= 0;) {
            ++count;
            h = m.cw(h);
            if (h == m.fan_start[v] || count > m.fan_size[v]) break;
        }
        if (count != m.fan_size[v]) first_split = std::min(first_split, i);
    }
    if (first_split < listed) {
        const int v = m.vertex_order[static_cast<std::size_t>(first_split)];
        return {ErrorCode::NonManifoldVertex,
                "the triangles around vertex " + std::to_string(m.input_vertex[v]) + " do not form a single fan (" +
                    what + ")",
                m.input_vertex[v]};
    }
    return {};
}

} // namespace qex::detail
