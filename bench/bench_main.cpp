// Benchmarks: BM_<Stage>/<input> on the paper's maps (from ../shared), on 1-to-4 subdivided
// versions made in memory (the integer-grid map is unchanged by midpoint subdivision), and on
// large generated maps. Per-stage times of the extraction are reported as counters.
#include "map_generators.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <map>
#include <string>

namespace {

namespace fs = std::filesystem;
using qex::Input;

/// 1-to-4 midpoint subdivision with linearly interpolated per-corner UVs.
Input subdivide(const Input& in) {
    Input out;
    out.positions = in.positions;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        const int id = static_cast<int>(out.positions.size());
        const auto& p = in.positions[a];
        const auto& q = in.positions[b];
        out.positions.push_back({0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])});
        mid.emplace(key, id);
        return id;
    };
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const auto& t = in.triangles[f];
        const auto* uv = &in.uvs[3 * f];
        const int m01 = midpoint(t[0], t[1]), m12 = midpoint(t[1], t[2]), m20 = midpoint(t[2], t[0]);
        auto half = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
            return std::array<double, 2>{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
        };
        const auto u01 = half(uv[0], uv[1]), u12 = half(uv[1], uv[2]), u20 = half(uv[2], uv[0]);
        out.triangles.push_back({t[0], m01, m20});
        out.uvs.insert(out.uvs.end(), {uv[0], u01, u20});
        out.triangles.push_back({m01, t[1], m12});
        out.uvs.insert(out.uvs.end(), {u01, uv[1], u12});
        out.triangles.push_back({m20, m12, t[2]});
        out.uvs.insert(out.uvs.end(), {u20, u12, uv[2]});
        out.triangles.push_back({m01, m12, m20});
        out.uvs.insert(out.uvs.end(), {u01, u12, u20});
    }
    return out;
}

void BM_Extract(benchmark::State& state, const Input* in) {
    std::map<std::string, double> stage;
    std::size_t quads = 0;
    for (auto _ : state) {
        const qex::Result r = qex::extract(*in);
        quads = r.mesh.faces.size();
        for (const auto& [name, s] : r.report.stage_seconds) stage[name] += s;
        benchmark::DoNotOptimize(r.mesh.faces.data());
    }
    for (const auto& [name, s] : stage) state.counters[name + "_ms"] = 1e3 * s / static_cast<double>(state.iterations());
    state.counters["quads"] = static_cast<double>(quads);
    state.counters["triangles"] = static_cast<double>(in->triangles.size());
}

void BM_Verify(benchmark::State& state, const Input* in) {
    const qex::Result r = qex::extract(*in);
    for (auto _ : state) benchmark::DoNotOptimize(qex::verify(*in, r.mesh).valid);
}

void BM_ReadObj(benchmark::State& state, std::string path) {
    const auto bytes = fs::file_size(path);
    for (auto _ : state) {
        Input in;
        benchmark::DoNotOptimize(qex::read_obj(path, in).ok());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}

std::vector<std::unique_ptr<Input>> inputs; // kept alive for the registered benchmarks

const Input* keep(Input in) {
    inputs.push_back(std::make_unique<Input>(std::move(in)));
    return inputs.back().get();
}

} // namespace

int main(int argc, char** argv) {
    const fs::path shared = fs::path(QEX_SHARED_DIR) / "meshes" / "paper";
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(shared, ec))
        if (e.path().extension() == ".obj") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) std::fprintf(stderr, "note: no maps in %s; only generated inputs are benchmarked\n", shared.c_str());
    for (const auto& path : files) {
        const std::string name = path.stem().string();
        Input in;
        if (!qex::read_obj(path.string(), in).ok()) continue;
        benchmark::RegisterBenchmark(("BM_ReadObj/" + name).c_str(), BM_ReadObj, path.string())->Unit(benchmark::kMillisecond);
        const Input* base = keep(std::move(in));
        benchmark::RegisterBenchmark(("BM_Extract/" + name).c_str(), BM_Extract, base)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("BM_Verify/" + name).c_str(), BM_Verify, base)->Unit(benchmark::kMillisecond);
        if (name == "duck_miq_8_param") {
            const Input* s1 = keep(subdivide(*base));
            const Input* s2 = keep(subdivide(*s1));
            benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub1").c_str(), BM_Extract, s1)->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub2").c_str(), BM_Extract, s2)->Unit(benchmark::kMillisecond);
            if (std::getenv("QEX_BENCH_LARGE")) {
                const Input* s3 = keep(subdivide(*s2));
                const Input* s4 = keep(subdivide(*s3));
                benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub3").c_str(), BM_Extract, s3)->Unit(benchmark::kMillisecond);
                benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub4").c_str(), BM_Extract, s4)->Unit(benchmark::kMillisecond);
            }
        }
    }
    // Generated maps: many quads per triangle count (scaled UVs) and large closed surfaces.
    for (int n : {8, 32}) {
        const Input* g = keep(qex::testing::make_map(qex::testing::torus_layout(32, 16), n, 8));
        benchmark::RegisterBenchmark(("BM_Extract/torus_512quads_x" + std::to_string(n * n)).c_str(), BM_Extract, g)
            ->Unit(benchmark::kMillisecond);
    }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
