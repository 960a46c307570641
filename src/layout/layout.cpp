// qex::extract_layout: the separatrices traced as a motorcycle graph (trace.cpp), the patches they
// cut the mesh into (patches.cpp), annuli cut across, and the independent check's verdict
// (check_layout.cpp) before anything is called valid.
#include "patches.h"
#include "quad_topology.h"
#include "trace.h"

#include <algorithm>
#include <numeric>

namespace qex {
namespace {

using layout::QuadTopology;

SeparatrixStart start_kind(const QuadTopology& t, int v) {
    if (t.boundary[v]) return SeparatrixStart::BoundaryVertex;
    return t.feature[v] ? SeparatrixStart::FeatureVertex : SeparatrixStart::IrregularVertex;
}

/// The traces from every special vertex, in canonical order (start vertex, then first edge).
void start_traces(const QuadTopology& t, layout::Motorcycles& m, std::vector<int>& special) {
    std::vector<std::pair<std::pair<int, int>, int>> starts; // (ranks of from and to, half-edge)
    for (int v = 0; v < t.vertices; ++v) {
        if (!t.on_cut(v) && t.valence(v) == 4) continue;
        const layout::VertexSpokes s = layout::spokes(t, v);
        if (s.special) special.push_back(v);
        for (const int h : s.traces) starts.push_back({{t.rank[v], t.rank[t.to(h)]}, h});
    }
    std::sort(starts.begin(), starts.end());
    for (const auto& s : starts) layout::add_trace(m, t.from(s.second), s.second, start_kind(t, t.from(s.second)));
}

/// The half-edges on separatrices or cuts.
std::vector<char> layout_halfedges(const QuadTopology& t, const layout::Motorcycles& m) {
    std::vector<char> is_layout = t.cut;
    for (int h = 0; h < 4 * t.faces; ++h)
        if (m.used[h]) is_layout[h] = 1;
    return is_layout;
}

/// The patches; annuli and rectangles glued to themselves are cut (and the patches found again) at most thrice over.
std::string find_patches(const QuadTopology& t, layout::Motorcycles& m, Layout& out) {
    for (int round = 0;; ++round) {
        const std::vector<char> is_layout = layout_halfedges(t, m);
        const std::vector<std::vector<int>> faces = layout::number_patches(t, is_layout, out.face_patch);
        std::vector<int> stamp(t.vertices, -1);
        out.patches.clear();
        bool cut = false;
        for (std::size_t p = 0; p < faces.size(); ++p) {
            layout::PatchShape s = layout::analyse_patch(t, is_layout, out.face_patch, faces[p], stamp);
            if (s.needs_cut && round < 3) {
                for (const int h : s.cuts) layout::add_trace(m, t.from(h), h, SeparatrixStart::Cut);
                out.notes.push_back(s.problem + ": cut across from its boundary vertex " +
                                    std::to_string(t.from(s.cuts[0])) +
                                    (s.cuts.size() > 1 ? " and " + std::to_string(t.from(s.cuts[1])) : ""));
                cut = true;
            } else if (!s.ok) {
                return "patch " + std::to_string(p) + " (face " + std::to_string(faces[p][0]) + ") is " + s.problem;
            }
            out.patches.push_back(std::move(s.patch));
        }
        if (!cut) return "";
        layout::run(t, m);
    }
}

/// The separatrices, canonically ordered.
void collect_separatrices(const QuadTopology& t, const layout::Motorcycles& m, Layout& out) {
    for (const layout::Trace& tr : m.traces)
        if (!tr.dropped) out.separatrices.push_back({tr.path, tr.start, tr.end});
    std::sort(out.separatrices.begin(), out.separatrices.end(), [&](const Separatrix& a, const Separatrix& b) {
        return std::make_pair(t.rank[a.vertices[0]], t.rank[a.vertices[1]]) <
               std::make_pair(t.rank[b.vertices[0]], t.rank[b.vertices[1]]);
    });
}

} // namespace

Layout extract_layout(const QuadMesh& mesh, const LayoutOptions& options) {
    Layout out;
    QuadTopology t;
    if (std::string e = layout::build_topology(mesh, options, t); !e.empty()) {
        out.error = "no layout: " + e;
        return out;
    }
    layout::Motorcycles m;
    start_traces(t, m, out.special_vertices);
    layout::run(t, m);
    if (std::string e = find_patches(t, m, out); !e.empty()) {
        out.error = e;
        return out;
    }
    collect_separatrices(t, m, out);
    out.adjacency = layout::patch_adjacency(t, out.face_patch);
    for (const Patch& p : out.patches)
        if (p.kind == PatchKind::Torus)
            out.notes.push_back("a closed component without special vertex (a torus): no separatrix, one patch of " +
                                std::to_string(p.u) + " x " + std::to_string(p.v) + " faces");
    out.error = check_layout(mesh, out, options);
    out.valid = out.error.empty();
    if (!out.valid) out.error = "the layout check rejects the layout: " + out.error;
    return out;
}

const char* to_string(SeparatrixStart s) {
    switch (s) {
        case SeparatrixStart::IrregularVertex: return "IrregularVertex";
        case SeparatrixStart::BoundaryVertex: return "BoundaryVertex";
        case SeparatrixStart::FeatureVertex: return "FeatureVertex";
        case SeparatrixStart::Cut: return "Cut";
    }
    return "?";
}

const char* to_string(SeparatrixEnd e) {
    switch (e) {
        case SeparatrixEnd::SpecialVertex: return "SpecialVertex";
        case SeparatrixEnd::Boundary: return "Boundary";
        case SeparatrixEnd::Feature: return "Feature";
        case SeparatrixEnd::Separatrix: return "Separatrix";
        case SeparatrixEnd::HeadOn: return "HeadOn";
    }
    return "?";
}

const char* to_string(PatchKind k) { return k == PatchKind::Torus ? "Torus" : "Rectangle"; }

} // namespace qex
