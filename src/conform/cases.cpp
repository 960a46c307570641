// The case list of `qex conform`: known and hostile maps drawn from a seed, and the user's maps;
// a generated case's map built from its recipe (the layout's exact map, then its steps).
#include "conform_internal.h"
#include "map_generators.h"
#include "map_transforms.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace qex {
namespace {

namespace fs = std::filesystem;
using conform_detail::Draw;

// The perturbations the paper handles (known cases) and those that break extractors (hostile).
const char* const kLayouts[] = {"torus", "cube", "icosahedron", "prism", "disk", "annulus"};
const char* const kKnownSteps[] = {"rechart", "shuffle", "translate", "rotate", "scale", "collapse", "noise"};
const char* const kHostile[] = {"fold",       "fold_at_singularity", "zero_area",
                                "near_2_52",  "dropped_triangle",    "duplicated_triangle",
                                "truncated",  "nan",                 "index_out_of_range"};

gen::QuadLayout layout_of(const std::string& name) {
    if (name == "torus") return gen::torus_layout();
    if (name == "cube") return gen::cube_layout();
    if (name == "icosahedron") return gen::icosahedron_layout();
    if (name.rfind("prism", 0) == 0) return gen::prism_layout(std::max(3, std::atoi(name.c_str() + 5)));
    if (name == "disk") return gen::disk_layout();
    if (name == "annulus") return gen::annulus_layout();
    throw std::invalid_argument("unknown layout '" + name + "'");
}

/// Index `fraction` (in [0, 1)) of `n` things.
std::size_t pick(double fraction, std::size_t n) {
    return std::min(n - 1, static_cast<std::size_t>(std::max(0.0, fraction) * static_cast<double>(n)));
}

/// The interior vertices a fold may be centred on: `singular` ones, or regular ones.
std::vector<int> fold_centres(const Input& in, bool singular) {
    const std::vector<int> cones = gen::singular_vertices(in);
    if (singular) return cones;
    std::vector<int> out;
    std::vector<char> boundary(in.positions.size(), 0), cone(in.positions.size(), 0);
    for (int v : cones) cone[v] = 1;
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : in.triangles)
        for (int c = 0; c < 3; ++c) ++edges[std::minmax(t[c], t[(c + 1) % 3])];
    for (const auto& [e, uses] : edges)
        if (uses == 1) boundary[e.first] = boundary[e.second] = 1;
    for (std::size_t v = 0; v < in.positions.size(); ++v)
        if (!boundary[v] && !cone[v]) out.push_back(static_cast<int>(v));
    return out;
}

void noise(Input& in, double eps, std::uint64_t seed) {
    Draw d(seed);
    for (auto& uv : in.uvs) uv = {uv[0] + eps * d.signed_unit(), uv[1] + eps * d.signed_unit()};
}

void drop_or_copy_triangle(Input& in, std::size_t f, bool drop) {
    if (drop) {
        in.triangles.erase(in.triangles.begin() + static_cast<std::ptrdiff_t>(f));
        in.uvs.erase(in.uvs.begin() + static_cast<std::ptrdiff_t>(3 * f),
                     in.uvs.begin() + static_cast<std::ptrdiff_t>(3 * f + 3));
        return;
    }
    in.triangles.push_back(in.triangles[f]);
    for (int c = 0; c < 3; ++c) in.uvs.push_back(in.uvs[3 * f + c]);
}

/// One step on the map; false when it is a step on the file's text instead.
bool apply_map_step(Input& in, const ConformStep& s) {
    const auto seed = static_cast<std::uint64_t>(s.a);
    const std::size_t nt = in.triangles.size();
    if (s.op == "rechart") gen::transforms::rechart(in, seed, static_cast<std::int64_t>(s.b));
    else if (s.op == "shuffle") gen::transforms::shuffle(in, seed);
    else if (s.op == "translate") gen::transforms::translate_uvs(in, std::llround(s.a), std::llround(s.b));
    else if (s.op == "rotate") gen::rotate(in, static_cast<int>(s.a));
    else if (s.op == "scale") gen::transforms::scale_uvs(in, std::llround(s.a));
    else if (s.op == "collapse") gen::insert_collapsed_edge(in, static_cast<int>(pick(s.a, nt)), static_cast<int>(s.b));
    else if (s.op == "noise") noise(in, s.a, static_cast<std::uint64_t>(s.b));
    else if (s.op == "zero_area")
        for (int i = 0; i < static_cast<int>(s.a); ++i) // crowded: all in one neighbourhood
            gen::insert_zero_area_triangle(in, static_cast<int>(pick(s.b, nt)), i % 3);
    else if (s.op == "dropped_triangle" || s.op == "duplicated_triangle")
        drop_or_copy_triangle(in, pick(s.a, nt), s.op == "dropped_triangle");
    else if (s.op == "fold" || s.op == "fold_at_singularity") {
        const std::vector<int> centres = fold_centres(in, s.op == "fold_at_singularity");
        if (centres.empty()) return true;
        const int v = centres[pick(s.a, centres.size())];
        if (s.op == "fold") gen::fold_patch(in, v, static_cast<int>(s.b), gen::PatchMotion::Translate, 1.5, 0.5);
        else gen::squeeze_fan(in, v, s.b);
    } else
        return false;
    return true;
}

/// A step on the OBJ text: cut short, a UV made NaN, a corner's index out of range.
void apply_text_step(std::string& text, const ConformStep& s) {
    if (s.op == "truncated") {
        text.resize(pick(s.a, text.size()));
        return;
    }
    const std::string key = s.op == "nan" ? "\nvt " : "\nf ";
    std::vector<std::size_t> at;
    for (std::size_t p = text.find(key); p != std::string::npos; p = text.find(key, p + 1)) at.push_back(p + 1);
    if (at.empty()) return;
    const std::size_t line = at[pick(s.a, at.size())], end = text.find('\n', line);
    const std::string replacement = s.op == "nan" ? "vt nan 0.5" : "f 1/1 2/2 999999999/3";
    text.replace(line, end - line, replacement);
}

ConformStep random_known_step(Draw& d, const std::string& op) {
    if (op == "rechart") return {op, double(d.below(1u << 20)), double(1 + d.below(1000))};
    if (op == "shuffle") return {op, double(d.below(1u << 20))};
    if (op == "translate") // huge: up to 2^20 grid units each way
        return {op, double(d.between(-(1 << 20), 1 << 20)), double(d.between(-(1 << 20), 1 << 20))};
    if (op == "rotate") return {op, double(1 + d.below(3))};
    if (op == "scale") return {op, double(2 << d.below(2))};
    if (op == "collapse") return {op, d.unit(), double(d.below(3))};
    return {"noise", std::pow(10.0, -7.0 - double(d.below(3))), double(d.below(1u << 20))};
}

ConformCase known_case(std::uint64_t seed, int i) {
    Draw d(conform_detail::case_seed(seed, "known", i));
    ConformCase c;
    ConformRecipe& r = c.recipe;
    r.layout = kLayouts[i % 6];
    if (r.layout == "prism") r.layout += std::to_string(3 + d.below(4));
    r.n = 1 + static_cast<int>(d.below(3));
    r.k = r.n + static_cast<int>(d.below(2)); // on the grid, or in general position (n, n + 1 coprime)
    r.diagonals = static_cast<int>(d.below(3));
    r.seed = d.below(1u << 20);
    std::vector<std::string> ops(std::begin(kKnownSteps), std::end(kKnownSteps));
    const std::size_t steps = d.below(4);
    for (std::size_t s = 0; s < steps && !ops.empty(); ++s) {
        const std::size_t j = d.below(ops.size());
        r.steps.push_back(random_known_step(d, ops[j]));
        ops.erase(ops.begin() + static_cast<std::ptrdiff_t>(j));
    }
    c.kind = "known";
    c.family = "known/" + std::string(kLayouts[i % 6]);
    c.expected_quads = conform_detail::expected_quads(r);
    return c;
}

ConformCase hostile_case(std::uint64_t seed, int i) {
    Draw d(conform_detail::case_seed(seed, "hostile", i));
    ConformCase c;
    ConformRecipe& r = c.recipe;
    const std::string op = kHostile[i % 9];
    r.layout = op == "fold_at_singularity" ? (d.below(2) ? "cube" : "icosahedron") : kLayouts[d.below(6)];
    r.n = 2 + static_cast<int>(d.below(2));
    r.k = op == "near_2_52" ? r.n : r.n + static_cast<int>(d.below(2));
    r.diagonals = static_cast<int>(d.below(3));
    r.seed = d.below(1u << 20);
    if (op == "fold") r.steps.push_back({op, d.unit(), double(1 + d.below(3))});
    else if (op == "fold_at_singularity") r.steps.push_back({op, d.unit(), 3.0 + double(d.below(4))});
    else if (op == "zero_area") r.steps.push_back({op, double(4 + d.below(8)), d.unit()});
    else if (op == "near_2_52") r.steps.push_back({"translate", 4503599627370496.0 - 1024, 4503599627370496.0 - 2048});
    else r.steps.push_back({op, d.unit()});
    c.kind = "hostile";
    c.family = "hostile/" + op;
    return c;
}

void number(std::vector<ConformCase>& cases, std::size_t from) {
    for (std::size_t i = from; i < cases.size(); ++i) {
        char index[24];
        std::snprintf(index, sizeof index, "%04zu", i - from);
        cases[i].name = cases[i].family + "/" + index;
        cases[i].generated = true;
    }
}

} // namespace

std::int64_t conform_detail::expected_quads(const ConformRecipe& r) {
    std::int64_t q = gen::expected_quads(layout_of(r.layout), r.n);
    for (const ConformStep& s : r.steps)
        if (s.op == "scale") q *= std::llround(s.a) * std::llround(s.a);
    return q;
}

std::string conform_map_text(const ConformCase& c) {
    const ConformRecipe& r = c.recipe;
    Input in = gen::make_map(layout_of(r.layout), r.n, r.k, r.diagonals, static_cast<std::uint32_t>(r.seed));
    std::vector<const ConformStep*> text_steps;
    for (const ConformStep& s : r.steps)
        if (!apply_map_step(in, s)) text_steps.push_back(&s);
    std::string text = gen::to_obj(in);
    for (const ConformStep* s : text_steps) apply_text_step(text, *s);
    return text;
}

std::string conform_describe(const ConformCase& c) {
    if (!c.generated) return c.map_path;
    const ConformRecipe& r = c.recipe;
    std::string out = r.layout + " n=" + std::to_string(r.n) + " k=" + std::to_string(r.k) + " diagonals=" +
                      std::to_string(r.diagonals) + " seed=" + std::to_string(r.seed);
    char step[96];
    for (const ConformStep& s : r.steps) {
        std::snprintf(step, sizeof step, "; %s %.17g %.17g", s.op.c_str(), s.a, s.b);
        out += step;
    }
    return out;
}

std::vector<ConformCase> conform_cases(const std::vector<std::string>& sets, int count, std::uint64_t seed,
                                       std::string* error) {
    std::vector<ConformCase> cases;
    for (const std::string& set : sets) {
        const std::size_t from = cases.size();
        if (set == "known" || set == "hostile") {
            for (int i = 0; i < count; ++i) cases.push_back(set == "known" ? known_case(seed, i) : hostile_case(seed, i));
            number(cases, from);
            continue;
        }
        std::vector<std::string> maps;
        if (!collect_map_files(set, maps)) {
            if (error) *error = "cannot read the folder or list '" + set + "' (nor is it known or hostile)";
            return {};
        }
        for (const std::string& m : maps) {
            ConformCase c;
            c.name = "user/" + fs::path(m).filename().string();
            c.family = "user";
            c.kind = "user";
            c.map_path = m;
            cases.push_back(c);
        }
    }
    return cases;
}

} // namespace qex
