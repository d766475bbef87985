// Marching-cube octree benchmark: build time and peak memory, extraction throughput at 10 priorities,
// Metro error of each level against the input mesh, the triangle-count curve against the tables of Hasup
// Lee's thesis ("Efficient Level-of-Detail Model Generation of 3D Objects using Prioritized Marching Cube
// Octree", KAIST 2007), and a single-resolution reference (vtkMarchingCubes on a dense signed-distance
// volume of the same field) where the volume is small enough to be cheap.
//
//   lodforge_bench_mcoctree [--models dragon,frag] [--resolutions 64,128,256,512] [--metro-resolution 256]
//                           [--vtk-max 128] [--samples N] [--repeat N] [--build-only] [--threads N]
//
// Build seconds are one build (the whole build_mc_octree: kd-tree, field, octree, numbering); input points
// per second = the file's vertices (before duplicates are merged) / seconds. --repeat N builds N times and
// reports the build with the least CPU time; --build-only prints the stage times instead of extracting.
// Peak memory is the process's peak resident set during the build (reset before each build through
// /proc/self/clear_refs) minus the resident set before it. Extraction is timed
// over repeated calls to McOctreeExtractor::extract (median of 5 timings, each >= 50 ms of calls); making the
// extractor (its tables, once per tree) is timed apart, in thread CPU time.

#include "bench_util.h"
#include "lodforge/error.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <malloc.h>
#include <time.h>

#ifdef LODFORGE_BENCH_HAVE_VTK
#include <vtkImageData.h>
#include <vtkMarchingCubes.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#endif

using namespace lodforge;
using Clock = std::chrono::steady_clock;

namespace {

using lodforge::bench::split;

long status_kb(const char* key) {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind(key, 0) == 0) return std::atol(line.c_str() + std::string(key).size());
    return 0;
}
void reset_peak() {
    std::ofstream f("/proc/self/clear_refs");
    f << "5";
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU time of this thread / of the process: on a shared, loaded machine the wall clock mostly measures
// the other jobs, while CPU time measures our work (cache sharing aside).
double cpu_seconds(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// printf into a string (the tables are printed after all resolutions of a model ran).
template <class... A> void appendf(std::string& out, const char* fmt, A... args) {
    char buf[512];
    std::snprintf(buf, sizeof buf, fmt, args...);
    out += buf;
}

using lodforge::bench::median;

struct Model {
    std::string key, label, path;
    double band;  // 0 for closed scans; open scans end near their border
};

#ifdef LODFORGE_BENCH_HAVE_VTK
struct Cloud {
    std::vector<Vec3f> p, n;
    std::size_t kdtree_get_point_count() const { return p.size(); }
    float kdtree_get_pt(std::size_t i, std::size_t d) const { return p[i][int(d)]; }
    template <class B> bool kdtree_get_bbox(B&) const { return false; }
};
#endif

}  // namespace

int main(int argc, char** argv) {
    const std::string data = LODFORGE_SHARED_DATA;
    const std::vector<Model> all = {
        {"dragon", "dragon_vrip (437K points)", data + "/scan-dragon/dragon_vrip.ply", 0},
        {"frag", "frag_115 (64K points, RGB)", data + "/color-open3d-frag115/frag_115.ply", 2.5},
        {"bunny", "bun_zipper (36K points)", data + "/scan-bunny/bun_zipper.ply", 0},
    };
    std::vector<std::string> models = {"dragon", "frag"};
    std::vector<std::size_t> resolutions = {64, 128, 256, 512};
    std::size_t metro_resolution = 256, vtk_max = 128, samples = 200000;
    int repeats = 1;           // builds per resolution (the table gives the one with the least CPU time)
    bool build_only = false;   // no extractor, extraction, metro or reference
    unsigned threads = 0;      // McOctreeParams::threads
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : std::string(); };
        if (a == "--models") {
            models = split(next());
        } else if (a == "--resolutions") {
            resolutions.clear();
            for (const auto& r : split(next())) resolutions.push_back(std::size_t(std::atol(r.c_str())));
        } else if (a == "--metro-resolution") {
            metro_resolution = std::size_t(std::atol(next().c_str()));
        } else if (a == "--vtk-max") {
            vtk_max = std::size_t(std::atol(next().c_str()));
        } else if (a == "--repeat") {
            repeats = std::max(1, std::atoi(next().c_str()));
        } else if (a == "--threads") {
            threads = unsigned(std::atoi(next().c_str()));
        } else if (a == "--build-only") {
            build_only = true;
        } else if (a == "--samples") {
            samples = std::size_t(std::atol(next().c_str()));
        } else {
            std::fprintf(stderr, "usage: %s [--models dragon,frag,bunny] [--resolutions 64,128,256,512] "
                                 "[--metro-resolution R] [--vtk-max R] [--samples N] [--repeat N] [--build-only] [--threads N]\n", argv[0]);
            return 2;
        }
    }

    for (const std::string& key : models) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
        if (it == all.end()) {
            std::fprintf(stderr, "unknown model %s\n", key.c_str());
            return 2;
        }
        Mesh input;
        try {
            input = read_mesh(it->path);
        } catch (const Error& e) {
            std::fprintf(stderr, "%s\n", e.what());
            return 1;
        }
        std::printf("\n### %s: %zu vertices, %zu triangles%s\n\n", it->label.c_str(), input.vertex_count(),
                    input.triangle_count(), it->band > 0 ? " (open scan: band 2.5 cubes)" : "");
        std::printf("| resolution | build s (wall) | build s (CPU, all threads) | M points/s (wall) | M points/s (CPU) | peak MB | leaves | nodes | priorities | triangles (all leaves) | tree MB | extractor s (CPU) | extractor MB | density warning |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        std::string extraction, curve, metro;
        appendf(extraction, "\nExtraction (output triangles per second; median of 5 timings, wall and thread CPU time):\n\n");
        appendf(extraction, "| resolution | priority | %% of max | triangles | nodes (seams) | ms (wall) | M tris/s (wall) | ms (CPU) | M tris/s (CPU) |\n|---|---|---|---|---|---|---|---|---|\n");
        appendf(curve, "\nTriangle curve (fraction of the full count at 20/40/60/80/100 %% of the priorities):\n\n");
        appendf(curve, "| curve | 20%% | 40%% | 60%% | 80%% | 100%% |\n|---|---|---|---|---|---|\n");
        appendf(curve, "| 003 ball joint (18,159) | 0.232 | 0.439 | 0.637 | 0.811 | 1 |\n");
        appendf(curve, "| 003 Venus (28,560) | 0.239 | 0.442 | 0.638 | 0.811 | 1 |\n");
        appendf(curve, "| 003 woman (107,074) | 0.206 | 0.378 | 0.524 | 0.758 | 1 |\n");
        std::vector<std::pair<std::size_t, float>> cube_sizes;
        std::vector<std::uint64_t> full_counts;
        for (std::size_t res : resolutions) {
            McOctreeParams p;
            p.resolution = res;
            p.band = it->band;
            p.threads = threads;
            McOctreeBuildResult r;
            double s = 0, cpu = 0;
            long before = 0, peak = 0;
            std::string runs;  // CPU / wall of every build, when repeated
            for (int rep = 0; rep < repeats; ++rep) {
                r = McOctreeBuildResult{};
                malloc_trim(0);  // give freed memory back, so the peak below is this build's
                const long rss = status_kb("VmRSS:");
                reset_peak();
                const auto t0 = Clock::now();
                const double c0 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID);
                const double m0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
                r = build_mc_octree(input, p);
                const double ws = seconds_since(t0);
                const double cs = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0;
                const double ms = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - m0;
                const long hwm = status_kb("VmHWM:");
                appendf(runs, "%s%.2f/%.2f/%.2f", rep ? ", " : "", cs, ms, ws);
                if (rep == 0 || cs < cpu) s = ws, cpu = cs, before = rss, peak = hwm;
            }
            // The calling thread's CPU time: on a machine shared with other jobs the wall clock is what the
            // scheduler grants; this thread's time is the build's critical path when the other threads'
            // shares end first (a lower bound of the wall clock of an idle machine with enough cores).
            if (repeats > 1) std::printf("resolution %zu, builds (CPU / calling thread's CPU / wall s): %s\n", res, runs.c_str());
            if (build_only) {
                std::string st;
                for (const McBuildStage& g : r.stages)
                    appendf(st, "%s%s %.3f/%.3f/%.3f", st.empty() ? "" : ", ", g.name.c_str(), g.cpu_s, g.thread_cpu_s, g.wall_s);
                std::printf("resolution %zu, stages of the least-CPU build (CPU / calling thread's CPU / wall s): %s; field "
                            "values %zu (%zu scattered)\n",
                            res, st.c_str(), r.field_samples, r.scattered_samples);
            }
            const McOctree& t = r.tree;
            const double bytes = double(t.nodes.size()) * 40 + double(t.vertex_ids.size()) * 4 +
                                 double(t.neighbours.size()) * 4 + double(t.positions.size()) * (t.has_colors() ? 40 : 24) +
                                 double(t.order.size()) * 12 + double(t.metric.size()) * 4;
            if (build_only) {
                std::printf("| %zu | %.2f | %.2f | %.2f | %.2f | %.0f | %zu | %zu | %zu | %llu | %.1f | | | %s |\n", res, s, cpu,
                            double(input.vertex_count()) / s * 1e-6, double(input.vertex_count()) / cpu * 1e-6,
                            double(peak - before) / 1024.0, r.leaf_cubes, t.nodes.size(), t.max_priority(),
                            static_cast<unsigned long long>(t.triangle_counts.back()), bytes / 1e6,
                            std::any_of(r.warnings.begin(), r.warnings.end(),
                                        [](const std::string& w) { return w.find("density") != std::string::npos; })
                                ? "yes"
                                : "");
                std::fflush(stdout);
                continue;
            }
            // The extractor's tables (made once per tree; the studio keeps the extractor with the tree).
            malloc_trim(0);
            const long rss0 = status_kb("VmRSS:");
            const double x0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
            McOctreeExtractor ex(t);
            const double extractor_cpu = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - x0;
            malloc_trim(0);  // the constructor's temporaries are gone
            const double extractor_mb = double(status_kb("VmRSS:") - rss0) / 1024.0;
            std::printf("| %zu | %.2f | %.2f | %.2f | %.2f | %.0f | %zu | %zu | %zu | %llu | %.1f | %.2f | %.0f | %s |\n", res, s, cpu,
                        double(input.vertex_count()) / s * 1e-6, double(input.vertex_count()) / cpu * 1e-6,
                        double(peak - before) / 1024.0, r.leaf_cubes, t.nodes.size(), t.max_priority(),
                        static_cast<unsigned long long>(t.triangle_counts.back()), bytes / 1e6, extractor_cpu, extractor_mb,
                        std::any_of(r.warnings.begin(), r.warnings.end(),
                                    [](const std::string& w) { return w.find("density") != std::string::npos; })
                            ? "yes"
                            : "");
            std::fflush(stdout);
            cube_sizes.emplace_back(res, t.cube_size);
            full_counts.push_back(t.triangle_counts.back());

            for (int k = 1; k <= 10; ++k) {
                const std::size_t i = std::size_t(k) * t.max_priority() / 10;
                std::vector<double> times, cpu_times;
                std::size_t tris = 0, nodes = 0, seams = 0;
                for (int rep = 0; rep < 5; ++rep) {
                    int calls = 0;
                    const auto w0 = Clock::now();
                    const double e0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
                    do {
                        const McExtraction& e = ex.extract(i);
                        tris = e.mesh.triangle_count(), nodes = e.active_nodes, seams = e.transition_nodes;
                        ++calls;
                    } while (seconds_since(w0) < 0.05);
                    times.push_back(seconds_since(w0) / calls);
                    cpu_times.push_back((cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - e0) / calls);
                }
                const double w = median(times), c = median(cpu_times);
                appendf(extraction, "| %zu | %zu | %d | %zu | %zu (%zu) | %.3f | %.1f | %.3f | %.1f |\n", res, i, 10 * k, tris,
                        nodes, seams, w * 1e3, double(tris) / w * 1e-6, c * 1e3, double(tris) / c * 1e-6);
            }

            const double full = double(t.triangle_counts.back());
            appendf(curve, "| ours, resolution %zu (%llu) |", res, static_cast<unsigned long long>(t.triangle_counts.back()));
            for (int k = 2; k <= 10; k += 2)
                appendf(curve, " %.3f |", double(mc_triangles_at(t, std::size_t(k) * t.max_priority() / 10)) / full);
            appendf(curve, "\n");

            if (input.triangle_count() > 0 && res == metro_resolution) {
                appendf(metro, "\nMetro error against the input (resolution %zu, %zu samples per surface; relative to the input's diagonal):\n\n", res, samples);
                appendf(metro, "| priority %% | triangles | Hausdorff | mean | RMS |%s\n|---|---|---|---|---|%s\n",
                        t.has_colors() ? " colour RMS (0-255) |" : "", t.has_colors() ? "---|" : "");
                for (int k = 1; k <= 10; ++k) {
                    const std::size_t i = std::size_t(k) * t.max_priority() / 10;
                    const Mesh& m = ex.extract(i).mesh;
                    DistanceParams dp;
                    dp.samples = samples;
                    dp.vertex_errors = false;
                    const DistanceResult d = compare(input, m, dp);
                    appendf(metro, "| %d | %zu | %.5f | %.6f | %.6f |", 10 * k, m.triangle_count(), d.hausdorff_relative,
                            d.mean_relative, d.rms_relative);
                    if (d.has_color_error) appendf(metro, " %.2f |", d.color_rms);
                    appendf(metro, "\n");
                }
            }
        }
        if (build_only) continue;
        std::printf("%s%s%s", extraction.c_str(), curve.c_str(), metro.c_str());
        std::fflush(stdout);

#ifdef LODFORGE_BENCH_HAVE_VTK
        // Reference: one marching cubes over a dense volume of the same signed distance (nearest point,
        // sign from its normal), at the resolutions where the dense volume is cheap.
        Cloud cloud;
        {
            Mesh pts = input;
            if (!pts.has_normals()) {
                pts.normals.assign(pts.positions.size(), Vec3f{});
                for (std::size_t f = 0; f + 2 < pts.indices.size(); f += 3) {
                    const auto a = pts.indices[f], b = pts.indices[f + 1], c = pts.indices[f + 2];
                    const Vec3f n = cross(pts.positions[b] - pts.positions[a], pts.positions[c] - pts.positions[a]);
                    pts.normals[a] = pts.normals[a] + n, pts.normals[b] = pts.normals[b] + n, pts.normals[c] = pts.normals[c] + n;
                }
            }
            for (std::size_t i = 0; i < pts.positions.size(); ++i) {
                const float l = length(pts.normals[i]);
                if (l > 0) cloud.p.push_back(pts.positions[i]), cloud.n.push_back(pts.normals[i] * (1 / l));
            }
        }
        using Kd = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, std::uint32_t>;
        Kd kd(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
        kd.buildIndex();
        bool header = false;
        for (std::size_t r = 0; r < cube_sizes.size(); ++r) {
            const std::size_t res = cube_sizes[r].first;
            if (res > vtk_max) continue;
            if (!header) {
                std::printf("\nSingle-resolution reference (dense volume + vtkMarchingCubes, same field, same cube size):\n\n");
                std::printf("| resolution | volume | field s (wall) | vtkMarchingCubes s (CPU) | VTK M tris/s (CPU) | VTK triangles | ours (all leaves) |\n|---|---|---|---|---|---|---|\n");
                header = true;
            }
            const Bounds b = input.bounds();
            const float h = cube_sizes[r].second;
            const int nx = int(std::ceil((b.max.x - b.min.x) / h)) + 7, ny = int(std::ceil((b.max.y - b.min.y) / h)) + 7,
                      nz = int(std::ceil((b.max.z - b.min.z) / h)) + 7;
            const Vec3f o = b.min - Vec3f{3, 3, 3} * h;
            vtkNew<vtkImageData> img;
            img->SetDimensions(nx, ny, nz);
            img->SetOrigin(o.x, o.y, o.z);
            img->SetSpacing(h, h, h);
            vtkNew<vtkFloatArray> scalars;
            scalars->SetNumberOfValues(vtkIdType(nx) * ny * nz);
            const auto t0 = Clock::now();
            for (int z = 0; z < nz; ++z)
                for (int y = 0; y < ny; ++y)
                    for (int x = 0; x < nx; ++x) {
                        const Vec3f v = o + Vec3f{float(x), float(y), float(z)} * h;
                        const float q[3] = {v.x, v.y, v.z};
                        std::uint32_t idx = 0;
                        float d2 = 0;
                        nanoflann::KNNResultSet<float, std::uint32_t> rs(1);
                        rs.init(&idx, &d2);
                        kd.findNeighbors(rs, q, nanoflann::SearchParams());
                        const float d = std::sqrt(d2);
                        scalars->SetValue((vtkIdType(z) * ny + y) * nx + x, dot(v - cloud.p[idx], cloud.n[idx]) < 0 ? -d : d);
                    }
            const double field_s = seconds_since(t0);
            img->GetPointData()->SetScalars(scalars);
            vtkNew<vtkMarchingCubes> mc;
            mc->SetInputData(img);
            mc->SetValue(0, 0.0);
            mc->ComputeNormalsOff();
            mc->ComputeScalarsOff();
            const double t1 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
            mc->Update();
            const double mc_s = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - t1;
            std::printf("| %zu | %dx%dx%d | %.2f | %.3f | %.1f | %lld | %llu |\n", res, nx, ny, nz, field_s, mc_s,
                        double(mc->GetOutput()->GetNumberOfPolys()) / mc_s * 1e-6,
                        static_cast<long long>(mc->GetOutput()->GetNumberOfPolys()),
                        static_cast<unsigned long long>(full_counts[r]));
        }
#endif
    }
    return 0;
}
