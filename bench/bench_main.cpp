// Benchmarks: BM_<Stage>/<input> on the paper's maps (from ../shared), on 1-to-4 subdivided
// versions made in memory (the integer-grid map is unchanged by midpoint subdivision), and on
// large generated maps. BM_Extract is the whole extraction (its stage times as counters), and
// BM_<stage> each stage of the pipeline's stage table as extract() runs it.
#include "heap_policy.h"
#include "map_generators.h"
#include "ladder/ladder.h"
#include "pipeline.h"
#include "qex/layout.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <map>
#include <string>

namespace {

namespace fs = std::filesystem;
using qex::Input;

void BM_Extract(benchmark::State& state, const Input* in) {
    std::map<std::string, double> stage;
    std::size_t quads = 0;
    for (auto _ : state) {
        const qex::Result r = qex::extract(*in);
        quads = r.mesh.faces.size();
        for (const auto& [name, s] : r.report.stage_seconds) stage[name] += s;
        benchmark::DoNotOptimize(r.mesh.faces.data());
    }
    for (const auto& [name, s] : stage)
        state.counters[name + "_ms"] = 1e3 * s / static_cast<double>(state.iterations());
    state.counters["quads"] = static_cast<double>(quads);
    state.counters["triangles"] = static_cast<double>(in->triangles.size());
}

/// BM_<stage>/<input>: one stage of the stage table (pipeline.h), as extract() runs it. Each
/// iteration runs the whole extraction and counts only the stage's own time, which the
/// extraction measures itself (Report::stage_seconds, summed over rounds and rungs): the
/// benchmark times exactly what extract() runs, under the stage's name.
void BM_Stage(benchmark::State& state, const Input* in, qex::detail::Stage stage) {
    const std::string name = qex::detail::stage_name(stage);
    for (auto _ : state) {
        const qex::Result r = qex::extract(*in);
        double seconds = -1.0;
        for (const auto& [label, s] : r.report.stage_seconds)
            if (label == name) seconds = std::max(seconds, 0.0) + s;
        if (seconds < 0) {
            state.SkipWithError("the stage does not run on this input (e.g. untangle where the first rung is valid)");
            break;
        }
        state.SetIterationTime(seconds);
    }
    state.counters["triangles"] = static_cast<double>(in->triangles.size());
}

/// BM_<stage>/<name> for every stage of the table, `iterations` runs each.
void register_stages(const std::string& name, const Input* in, int iterations) {
    for (int s = 0; s < qex::detail::kNumStages; ++s) {
        const auto stage = static_cast<qex::detail::Stage>(s);
        benchmark::RegisterBenchmark(("BM_" + std::string(qex::detail::stage_name(stage)) + "/" + name).c_str(),
                                     BM_Stage, in, stage)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(iterations);
    }
}

/// BM_repair/<folder>/<map>: stage repair alone, on the map as given sanitized (what the
/// repaired rung hands it), each iteration on a freshly sanitized map; manual time of the repair only.
void BM_Repair(benchmark::State& state, const Input* in) {
    std::int64_t repaired = 0, unrepaired = 0;
    for (auto _ : state) {
        // The sanitized map is made afresh (TriMesh does not copy); only the repair is timed.
        qex::detail::TriMesh m;
        qex::Report report;
        if (!qex::detail::sanitize_as_given(*in, qex::Options{}, m, report)) {
            state.SkipWithError("the map is rejected before stage repair");
            return;
        }
        const auto start = std::chrono::steady_clock::now();
        const qex::detail::RepairOutcome out = qex::detail::repair(m, in->feature_edges, !in->valences.empty(), 1, report);
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        repaired = static_cast<std::int64_t>(out.repaired_faces.size());
        unrepaired = static_cast<std::int64_t>(out.unrepaired.size());
    }
    state.counters["repaired_triangles"] = static_cast<double>(repaired);
    state.counters["unrepaired_regions"] = static_cast<double>(unrepaired);
    state.counters["triangles"] = static_cast<double>(in->triangles.size());
}

/// Registers BM_repair for every map with a flipped or degenerate triangle in the shared folders.
void register_repairs(const fs::path& meshes, std::vector<std::unique_ptr<Input>>& kept) {
    for (const char* folder : {"paper", "miq", "miq-more", "quadcover"}) {
        std::error_code ec;
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(meshes / folder, ec))
            if (e.path().extension() == ".obj") files.push_back(e.path());
        std::sort(files.begin(), files.end());
        for (const auto& path : files) {
            Input in;
            if (!qex::read_obj(path.string(), in).ok()) continue;
            kept.push_back(std::make_unique<Input>(std::move(in)));
            const std::string name = std::string(folder) + "/" + path.stem().string();
            benchmark::RegisterBenchmark(("BM_repair/" + name).c_str(), BM_Repair, kept.back().get())
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(3);
        }
    }
}

void BM_Verify(benchmark::State& state, const Input* in) {
    const qex::Result r = qex::extract(*in);
    for (auto _ : state) benchmark::DoNotOptimize(qex::verify(*in, r.mesh).valid);
}

/// The quad layout of the extraction of `in` (issue 33), its check included.
void BM_Layout(benchmark::State& state, const Input* in) {
    const qex::Result r = qex::extract(*in);
    for (auto _ : state) benchmark::DoNotOptimize(qex::extract_layout(r.mesh).valid);
}

/// Reads an OBJ file with `threads` (0: every core).
void BM_ReadObj(benchmark::State& state, std::string path, int threads) {
    const auto bytes = fs::file_size(path);
    for (auto _ : state) {
        Input in;
        benchmark::DoNotOptimize(qex::read_obj(path, in, threads).ok());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}

/// Writes the extraction of `in` as OBJ; bytes per second of the written file.
void BM_WriteObj(benchmark::State& state, const Input* in, std::string path) {
    const qex::QuadMesh mesh = qex::extract(*in).mesh;
    for (auto _ : state) benchmark::DoNotOptimize(qex::write_obj(path, mesh).ok());
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * fs::file_size(path)));
    state.counters["quads"] = static_cast<double>(mesh.faces.size());
    fs::remove(path);
}

/// A scratch file in the system's temporary directory, removed at exit.
std::string scratch(const std::string& name, const std::string& text) {
    static std::vector<std::string> files;
    static const struct Cleanup {
        ~Cleanup() {
            std::error_code ec;
            for (const auto& f : files) fs::remove(f, ec);
        }
    } cleanup;
    const std::string path = (fs::temp_directory_path() / ("qex_bench_" + name)).string();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return {};
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
    files.push_back(path);
    return path;
}

std::vector<std::unique_ptr<Input>> inputs; // kept alive for the registered benchmarks

const Input* keep(Input in) {
    inputs.push_back(std::make_unique<Input>(std::move(in)));
    return inputs.back().get();
}

} // namespace

int main(int argc, char** argv) {
    // The program's heap policy: figures are of the extraction on reused memory, as in the CLI,
    // not of this VM's first-touch page faults (bench/RESULTS.md has both).
    qex::cli::prepare_heap(std::uintmax_t{2} << 30);
    const fs::path shared = fs::path(QEX_SHARED_DIR) / "meshes" / "paper";
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(shared, ec))
        if (e.path().extension() == ".obj") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty())
        std::fprintf(stderr, "note: no maps in %s; only generated inputs are benchmarked\n", shared.c_str());
    for (const auto& path : files) {
        const std::string name = path.stem().string();
        Input in;
        if (!qex::read_obj(path.string(), in).ok()) continue;
        benchmark::RegisterBenchmark(("BM_ReadObj/" + name).c_str(), BM_ReadObj, path.string(), 0)
            ->Unit(benchmark::kMillisecond);
        const Input* base = keep(std::move(in));
        benchmark::RegisterBenchmark(("BM_Extract/" + name).c_str(), BM_Extract, base)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("BM_Verify/" + name).c_str(), BM_Verify, base)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("BM_Layout/" + name).c_str(), BM_Layout, base)->Unit(benchmark::kMillisecond);
        register_stages(name, base, 30);
        if (name == "duck_miq_8_param") {
            const Input* s1 = keep(qex::testing::subdivide(*base));
            const Input* s2 = keep(qex::testing::subdivide(*s1));
            benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub1").c_str(), BM_Extract, s1)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub2").c_str(), BM_Extract, s2)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("BM_Verify/" + name + "_sub2").c_str(), BM_Verify, s2)
                ->Unit(benchmark::kMillisecond);
            register_stages(name + "_sub1", s1, 10);
            register_stages(name + "_sub2", s2, 4);
            // The reader on the twice-subdivided duck as a file (61 MB), serial and on 2 threads.
            if (const std::string file = scratch(name + "_sub2.obj", qex::testing::to_obj(*s2)); !file.empty())
                for (int t : {1, 2})
                    benchmark::RegisterBenchmark(("BM_ReadObj/" + name + "_sub2/threads:" + std::to_string(t)).c_str(),
                                                 BM_ReadObj, file, t)
                        ->Unit(benchmark::kMillisecond);
            if (std::getenv("QEX_BENCH_LARGE")) {
                const Input* s3 = keep(qex::testing::subdivide(*s2));
                const Input* s4 = keep(qex::testing::subdivide(*s3));
                benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub3").c_str(), BM_Extract, s3)
                    ->Unit(benchmark::kMillisecond);
                benchmark::RegisterBenchmark(("BM_Extract/" + name + "_sub4").c_str(), BM_Extract, s4)
                    ->Unit(benchmark::kMillisecond);
            }
        }
    }
    // Generated maps: many quads per triangle count (scaled UVs) and large closed surfaces.
    // Scaled UVs on the same 65,536 triangles: 64, 1024 and (with QEX_BENCH_LARGE) 6400 quads
    // per layout quad, 100x the first.
    std::vector<int> scales{8, 32};
    if (std::getenv("QEX_BENCH_LARGE")) scales.push_back(80);
    for (int n : scales) {
        const Input* g = keep(qex::testing::make_map(qex::testing::torus_layout(32, 16), n, 8));
        benchmark::RegisterBenchmark(("BM_Extract/torus_512quads_x" + std::to_string(n * n)).c_str(), BM_Extract, g)
            ->Unit(benchmark::kMillisecond);
        if (n <= 32) register_stages("torus_512quads_x" + std::to_string(n * n), g, n == 8 ? 10 : 2);
        if (n == 32)
            benchmark::RegisterBenchmark("BM_WriteObj/torus_512quads_x1024", BM_WriteObj, g,
                                         (fs::temp_directory_path() / "qex_bench_write.obj").string())
                ->Unit(benchmark::kMillisecond);
    }
    register_repairs(fs::path(QEX_SHARED_DIR) / "meshes", inputs);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
