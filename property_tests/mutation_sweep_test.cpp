// The mutation sweep (issue 31): on qex's output of every shared map, judged without provenance as
// `qex check --param` judges another tool's mesh, edges rotated between two quads, quads dropped
// and vertices slid along the surface off their grid points. Each mutant must be rejected naming
// its place, or left undecided (named in VerifyResult::undecided); none may pass unnoticed. The
// unmutated outputs must pass. The tallies print per map (property_tests/README.md lists them).
// Mutants of one kind are applied together, each a face apart from the others, and judged at once.
// Rotated edges the given map leaves undecided are judged again on the output's certificate
// (qex::Certificate, the repaired map), where they must not pass unnoticed either.
#include "mutations.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

namespace qex::testing {
namespace {

namespace fs = std::filesystem;
using Index = std::int64_t;

/// Most mutants of each kind per map (every one on small meshes).
constexpr std::size_t kRotations = 200, kDrops = 40, kSlides = 40;
/// Rounds of rotations (each judged at once, its sites a face apart): on small meshes the 200
/// edges sampled do not all fit in them; the rest are left out.
constexpr int kRounds = 4;

/// Per kind: rejected (a violation names its place), undecided (an undecided check does), missed.
struct Tally {
    std::size_t rejected = 0, undecided = 0, missed = 0;
};

using SiteList = std::vector<std::pair<std::set<Index>, std::set<Index>>>;

/// Tallies each site (its vertices and faces) of the verdict `v` into `t`; returns the indices
/// of the sites left undecided.
std::vector<std::size_t> tally(const VerifyResult& v, const SiteList& sites, Tally& t) {
    std::vector<std::size_t> undecided;
    for (std::size_t i = 0; i < sites.size(); ++i) {
        if (named(v.violations, sites[i].first, sites[i].second)) {
            ++t.rejected;
        } else if (named(v.undecided, sites[i].first, sites[i].second)) {
            ++t.undecided;
            undecided.push_back(i);
        } else {
            ++t.missed;
        }
    }
    return undecided;
}

/// Judges `m` on the given map and tallies each site into `t`; returns the indices of the sites
/// left undecided.
std::vector<std::size_t> judge(const Input& in, const QuadMesh& m, const SiteList& sites, Tally& t) {
    if (sites.empty()) return {};
    return tally(verify(in, m), sites, t);
}

/// The interior edges whose two quads have six distinct vertices, each once.
std::vector<SharedEdge> rotatable_edges(const QuadMesh& m) {
    std::map<std::pair<int, int>, std::size_t> side;
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (std::size_t i = 0; i < 4; ++i) side[{m.faces[f][i], m.faces[f][(i + 1) % 4]}] = f;
    std::vector<SharedEdge> edges;
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (std::size_t i = 0; i < 4; ++i) {
            const int a = m.faces[f][i], b = m.faces[f][(i + 1) % 4];
            const auto it = side.find({b, a});
            if (it == side.end() || it->second <= f) continue;
            std::set<int> six(m.faces[f].begin(), m.faces[f].end());
            six.insert(m.faces[it->second].begin(), m.faces[it->second].end());
            if (six.size() == 6) edges.push_back({f, it->second, a, b});
        }
    return edges;
}

/// Rotates in `m` (a copy of `good`) the edges of `todo` that lie a face apart, in order: their
/// sites into `judged`, the edges into `placed`, the others into `later`.
void place_rotations(const QuadMesh& good, const std::vector<SharedEdge>& todo, QuadMesh& m, SiteList& judged,
                     std::vector<SharedEdge>& placed, std::vector<SharedEdge>& later) {
    Sites sites(good);
    for (const SharedEdge& e : todo) {
        if (!rotate_apart(sites, good, m, e)) {
            later.push_back(e);
            continue;
        }
        placed.push_back(e);
        const std::vector<int> site = edge_site(good, e);
        judged.push_back(
            {std::set<Index>(site.begin(), site.end()), {static_cast<Index>(e.f), static_cast<Index>(e.g)}});
    }
}

/// Rotated edges (rotate_edge: a and b lose a face, the far corners x of f and z of g gain
/// one), spread over the mesh (every k-th), in up to kRounds rounds. Those the given map leaves
/// undecided are judged again on the output's certificate where it lists repaired triangles (a
/// certificate without is the sanitized map), in one round: those a face apart, into
/// `on_certificate` (the others are not judged again).
Tally rotate_edges(const Input& in, const QuadMesh& good, const Certificate& certificate, Tally& on_certificate) {
    Tally t;
    const std::vector<SharedEdge> edges = rotatable_edges(good);
    const std::size_t stride = std::max<std::size_t>(1, edges.size() / kRotations);
    std::vector<SharedEdge> todo, undecided;
    for (std::size_t i = 0; i < edges.size() && todo.size() < kRotations; i += stride) todo.push_back(edges[i]);
    for (int round = 0; round < kRounds && !todo.empty(); ++round) {
        QuadMesh m = good;
        SiteList judged;
        std::vector<SharedEdge> placed, later;
        place_rotations(good, todo, m, judged, placed, later);
        for (std::size_t i : judge(in, m, judged, t)) undecided.push_back(placed[i]);
        if (later.size() == todo.size()) break;
        todo = std::move(later);
    }
    if (undecided.empty() || certificate.repaired.empty()) return t;
    QuadMesh m = good;
    SiteList judged;
    std::vector<SharedEdge> placed, later;
    place_rotations(good, undecided, m, judged, placed, later);
    tally(verify(in, m, certificate), judged, on_certificate);
    return t;
}

/// Dropped quads off the boundary (a quad dropped at a boundary off the iso-lines is a dent in
/// its staircase, which no check can tell from one), every k-th, a face apart: holes.
Tally drop_faces(const Input& in, const QuadMesh& good) {
    Tally t;
    Sites sites(good);
    std::set<std::pair<int, int>> sides;
    for (const auto& f : good.faces)
        for (std::size_t i = 0; i < 4; ++i) sides.insert({f[i], f[(i + 1) % 4]});
    std::set<int> boundary;
    for (const auto& s : sides)
        if (!sides.count({s.second, s.first})) boundary.insert(s.first), boundary.insert(s.second);
    for (int v : boundary) sites.block(v);
    SiteList judged;
    std::vector<char> drop(good.faces.size(), 0);
    const std::size_t stride = std::max<std::size_t>(1, good.faces.size() / (2 * kDrops));
    for (std::size_t f = stride / 2; f < good.faces.size() && judged.size() < kDrops; f += stride) {
        if (!sites.claim(good.faces[f])) continue;
        drop[f] = 1;
        judged.push_back({std::set<Index>(good.faces[f].begin(), good.faces[f].end()), {}});
    }
    QuadMesh m = good;
    m.faces.clear();
    for (std::size_t f = 0; f < good.faces.size(); ++f)
        if (!drop[f]) m.faces.push_back(good.faces[f]);
    judge(in, m, judged, t);
    return t;
}

/// Vertices slid along the surface: onto the centroid of the input triangle their provenance
/// names (off the grid: centroids within 0.05 of a grid point are left out), every k-th, a face
/// apart.
Tally slide_vertices(const Input& in, const QuadMesh& good, const std::vector<Provenance>& provenance) {
    Tally t;
    Sites sites(good);
    QuadMesh m = good;
    SiteList judged;
    const std::size_t stride = std::max<std::size_t>(1, good.positions.size() / (2 * kSlides));
    for (std::size_t v = stride / 2; v < good.positions.size() && judged.size() < kSlides; v += stride) {
        const Provenance& p = provenance[v];
        const int tri = p.kind == QVertexKind::Vertex ? p.chart_triangle : p.element;
        if (tri < 0) continue;
        // The centroid's UV (at the mesh's grid scale): a centroid near a grid point may be a
        // preimage of one, where a vertex may lie.
        double uv[2] = {0, 0};
        for (std::size_t k = 0; k < 3; ++k)
            for (int d = 0; d < 2; ++d) uv[d] += in.uvs[3 * static_cast<std::size_t>(tri) + k][d] * good.grid_scale / 3;
        if (std::abs(uv[0] - std::nearbyint(uv[0])) < 0.05 && std::abs(uv[1] - std::nearbyint(uv[1])) < 0.05) continue;
        if (!sites.claim({static_cast<int>(v)})) continue;
        std::array<double, 3> c{0, 0, 0};
        for (int k : in.triangles[static_cast<std::size_t>(tri)])
            for (int d = 0; d < 3; ++d) c[d] += in.positions[static_cast<std::size_t>(k)][d] / 3;
        m.positions[v] = c;
        std::set<Index> faces;
        for (std::size_t f : sites.faces_at(static_cast<int>(v))) faces.insert(static_cast<Index>(f));
        judged.push_back({{static_cast<Index>(v)}, faces});
    }
    judge(in, m, judged, t);
    return t;
}

std::string line(const char* kind, const Tally& t) {
    char buf[96];
    std::snprintf(buf, sizeof buf, " %s %zu/%zu/%zu", kind, t.rejected, t.undecided, t.missed);
    return buf;
}

/// Every shared map, as folder/file: one test each.
std::vector<std::string> shared_maps() {
    std::vector<std::string> out;
    for (const char* dir : {"paper", "miq", "miq-more", "quadcover"}) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(fs::path(QEX_SHARED_DIR) / "meshes" / dir, ec))
            if (e.path().extension() == ".obj") out.push_back(std::string(dir) + "/" + e.path().filename().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string map_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string s = fs::path(info.param).stem().string();
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

class MutationSweep : public ::testing::TestWithParam<std::string> {};

// One test per map (ctest runs them side by side); each prints its tallies, which
// property_tests/README.md sums.
TEST_P(MutationSweep, EveryMutantOfTheOutputIsRejectedOrUndecided) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / GetParam();
    Input in;
    ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
    const Result r = extract(in);
    if (!r.ok() || !r.check.valid) GTEST_SKIP() << path << ": no valid mesh to mutate";
    QuadMesh good = bare(r.mesh);
    good.grid_scale = r.mesh.grid_scale;
    const VerifyResult own = verify(in, good);
    EXPECT_TRUE(own.valid) << path << ": " << first_message(own);
    const Certificate certificate = make_certificate(in, r.mesh);
    Tally on_certificate;
    const Tally t[3] = {rotate_edges(in, good, certificate, on_certificate), drop_faces(in, good),
                        slide_vertices(in, good, r.mesh.provenance)};
    std::printf(
        "%-34s rotated%s dropped%s slid%s (rejected/undecided/missed); rotated undecided, on the "
        "certificate%s\n",
        path.stem().c_str(), line("", t[0]).c_str(), line("", t[1]).c_str(), line("", t[2]).c_str(),
        line("", on_certificate).c_str());
    EXPECT_EQ(on_certificate.missed, 0u) << path << " on its certificate";
    for (int k = 0; k < 3; ++k) EXPECT_EQ(t[k].missed, 0u) << path << " kind " << k;
    EXPECT_EQ(t[1].undecided, 0u) << path << ": a dropped quad is a hole, decided everywhere";
}

// Every shared map, none where ../shared is absent.
INSTANTIATE_TEST_SUITE_P(SharedMaps, MutationSweep, ::testing::ValuesIn(shared_maps()), map_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(MutationSweep);

} // namespace
} // namespace qex::testing
