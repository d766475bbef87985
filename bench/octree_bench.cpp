// Out-of-core octree benchmark: `lodforge octree build` (soup conversion, octree, node simplification)
// and its OoCS mode against vtkQuadricClustering, on the dragon and on a ≥ 10M-triangle binary PLY made
// from it at run time (1-to-4 midpoint subdivision, twice), at memory budgets of 16, 64 and 256 MB.
//
// Every build runs as its own child process (the real CLI, fork + exec) so its peak resident memory is
// the kernel's ru_maxrss from wait4, not an estimate; vtkQuadricClustering runs in a forked child too
// (in-core: PLY read into memory, then the filter). Printed: stage times and million input
// triangles/s (soup conversion, octree, simplification, end to end = wall clock of the child), peak
// RSS, the triangles of every level, and the Metro error (lodforge compare(), symmetric, relative to the
// bounding-box diagonal) of every level of the dragon asset and of both clustering outputs.
//
//   lodforge_bench_octree [--quick] [--budgets 16,64,256] [--max-triangles N] [--grid N] [--samples N]
//
// --quick: the dragon only. The generated PLY lives in a temporary directory that is removed at exit
// (--generated PATH: kept there, and reused when it exists).
#include "lodforge/error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/io/temp_directory.h"
#include "lodforge/octree/ooc_soup.h"
#include "lodforge/io/ply.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <unordered_map>
#include <vector>

#ifdef LODFORGE_BENCH_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricClustering.h>
#endif

using namespace lodforge;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

struct ChildRun {
    int exit_code = -1;
    long peak_kb = 0;
    double wall = 0;
    double cpu = 0;  // user + system seconds of the child and its threads (load-independent, unlike wall)
    std::string out;
};

// Runs f in a forked child; whatever it writes to the given FILE* comes back in `out`.
ChildRun run_child(const std::function<void(FILE*)>& f) {
    int fds[2];
    if (::pipe(fds) != 0) return {};
    std::fflush(stdout);
    const Clock::time_point t0 = Clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(fds[0]);
        FILE* w = ::fdopen(fds[1], "w");
        int code = 0;
        try {
            f(w);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child failed: %s\n", e.what());
            code = 1;
        }
        std::fclose(w);
        ::_exit(code);
    }
    ::close(fds[1]);
    ChildRun r;
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fds[0], buf, sizeof buf)) > 0) r.out.append(buf, static_cast<std::size_t>(n));
    ::close(fds[0]);
    int status = 0;
    rusage usage{};
    ::wait4(pid, &status, 0, &usage);
    r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.peak_kb = usage.ru_maxrss;
    r.cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
            1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    return r;
}

std::string lodforge_cli() { return (fs::read_symlink("/proc/self/exe").parent_path() / "lodforge").string(); }

// The CLI in a child (exec), stdout captured.
ChildRun run_cli(const std::vector<std::string>& args) {
    return run_child([&](FILE* w) {
        ::dup2(::fileno(w), 1);
        std::vector<char*> argv;
        const std::string bin = lodforge_cli();
        argv.push_back(const_cast<char*>(bin.c_str()));
        argv.push_back(const_cast<char*>("--quiet"));
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(bin.c_str(), argv.data());
        ::_exit(127);
    });
}

double number_after(const std::string& text, const std::string& key) {
    const std::size_t at = text.find(key);
    return at == std::string::npos ? -1 : std::atof(text.c_str() + at + key.size());
}

// 1-to-4 midpoint subdivision (positions only).
Mesh subdivide(const Mesh& in) {
    Mesh out;
    out.positions = in.positions;
    std::unordered_map<std::uint64_t, std::uint32_t> mid;
    mid.reserve(in.indices.size());
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t key = a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
        auto [it, inserted] = mid.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
        if (inserted) out.positions.push_back((out.positions[a] + out.positions[b]) * 0.5f);
        return it->second;
    };
    out.indices.reserve(in.indices.size() * 4);
    for (std::size_t t = 0; t < in.triangle_count(); ++t) {
        const std::uint32_t a = in.indices[3 * t], b = in.indices[3 * t + 1], c = in.indices[3 * t + 2];
        const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
        for (std::uint32_t v : {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca}) out.indices.push_back(v);
    }
    return out;
}

struct Model {
    std::string label, path;
    std::uint64_t triangles = 0;
    double file_mb = 0;
    bool metro = false;
};

std::vector<int> parse_list(const std::string& s) {
    std::vector<int> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(std::atoi(item.c_str()));
    return out;
}

DistanceParams metro_params(std::size_t samples) {
    DistanceParams p;
    p.samples = samples;
    p.vertex_errors = false;
    return p;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    std::vector<int> budgets{16, 64, 256};
    std::size_t max_triangles = 5000, grid = 256, samples = 200000;
    std::string generated;  // --generated PATH: keep (and reuse) the generated PLY there
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--quick") quick = true;
        else if (a == "--budgets") budgets = parse_list(next());
        else if (a == "--max-triangles") max_triangles = std::stoul(next());
        else if (a == "--grid") grid = std::stoul(next());
        else if (a == "--samples") samples = std::stoul(next());
        else if (a == "--generated") generated = next();
        else {
            std::fprintf(stderr, "usage: %s [--quick] [--budgets 16,64,256] [--max-triangles N] [--grid N] [--samples N] [--generated PATH]\n", argv[0]);
            return 2;
        }
    }
    if (!fs::exists(lodforge_cli())) {
        std::fprintf(stderr, "the lodforge CLI must be built beside this benchmark (%s)\n", lodforge_cli().c_str());
        return 1;
    }
    // The machine is shared: the load says how far wall clocks are from what the CPU time allows.
    auto print_load = [](const char* when) {
        double load[3] = {0, 0, 0};
        if (::getloadavg(load, 3) > 0) std::printf("load average %s: %.1f %.1f %.1f\n\n", when, load[0], load[1], load[2]);
    };
    print_load("at the start");
    try {
        TempDirectory tmp(fs::temp_directory_path().string());
        std::vector<Model> models;
        const std::string dragon = std::string(LODFORGE_SHARED_DATA) + "/scan-dragon/dragon_vrip.ply";
        models.push_back({"dragon_vrip (ASCII)", dragon, 871414, static_cast<double>(fs::file_size(dragon)) / 1e6, true});
        if (!quick) {
            const std::string big = generated.empty() ? tmp.file("dragon_x16.ply") : generated;
            const ChildRun g = run_child([&](FILE* w) {
                if (fs::exists(big)) {
                    const PlyReader r(big);
                    for (const PlyElement& e : r.header().elements)
                        if (e.name == "face") std::fprintf(w, "%llu\n", static_cast<unsigned long long>(e.count));
                    return;
                }
                const Mesh d = read_ply(dragon);
                const Mesh m = subdivide(subdivide(d));
                write_ply(m, big);
                std::fprintf(w, "%zu %zu\n", m.triangle_count(), m.vertex_count());
            });
            if (g.exit_code != 0) throw Error(Error::Kind::io, "generating the subdivided dragon failed");
            const std::uint64_t t = std::strtoull(g.out.c_str(), nullptr, 10);
            std::printf("generated %s: %llu triangles, %.0f MB binary PLY, in %.1f s\n\n", big.c_str(),
                        static_cast<unsigned long long>(t), static_cast<double>(fs::file_size(big)) / 1e6, g.wall);
            models.push_back({"dragon ×16 (binary, generated)", big, t, static_cast<double>(fs::file_size(big)) / 1e6, false});
        }

        std::printf("## octree build (max %zu triangles per leaf, max depth 12)\n\n", max_triangles);
        std::printf("| model | budget MB | soup s | octree s (incl. simplify) | simplify s (2 threads, summed) | end to end s | "
                    "M tris/s soup | M tris/s octree | M tris/s simplify | M tris/s end to end | CPU s (user + sys) | M tris per CPU s | "
                    "peak RSS MB | ≤ budget+64 | soup path |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        std::vector<std::string> level_lines;
        for (const Model& m : models) {
            for (int budget : budgets) {
                const std::string asset = tmp.file("asset.lfo");
                const ChildRun r = run_cli({"octree", "build", m.path, "-o", asset, "--max-triangles",
                                            std::to_string(max_triangles), "--memory", std::to_string(budget),
                                            "--temp-dir", tmp.path()});
                if (r.exit_code != 0) throw Error(Error::Kind::io, "octree build failed on " + m.path + ": " + r.out);
                const std::string times = r.out.substr(r.out.find("time: soup "));
                const double soup = number_after(times, "time: soup "), oct = number_after(times, "octree "),
                             simp = number_after(times, "simplification ");
                const double mt = static_cast<double>(m.triangles) / 1e6;
                const double peak = static_cast<double>(r.peak_kb) / 1024.0;
                std::printf("| %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %s | %s |\n",
                            m.label.c_str(), budget, soup, oct, simp, r.wall, mt / soup, mt / oct, mt / simp, mt / r.wall, r.cpu,
                            mt / r.cpu, peak,
                            peak <= budget + 64 ? "yes" : "**no**",
                            r.out.find("external sort") != std::string::npos ? "external sort (3 passes)" : "in memory (1 pass)");
                std::fflush(stdout);
                if (budget == budgets.back()) {
                    const std::size_t at = r.out.find("triangles per level:");
                    level_lines.push_back(m.label + ": " + r.out.substr(at, r.out.find('\n', at) - at));
                    if (m.metro) {
                        // Metro error of every level against the input (in a child: the input is big).
                        const ChildRun e = run_child([&](FILE* w) {
                            const Mesh in = read_ply(m.path);
                            OctreeStore store(asset);
                            for (int level = 1; level < store.level_count(); ++level) {
                                const Mesh lm = extract_mesh(store, level_cut(store, level));
                                const DistanceResult d = compare(in, lm, metro_params(samples));
                                std::fprintf(w, "| %d | %zu | %.3g | %.3g | %.3g |\n", level, lm.triangle_count(), d.mean,
                                             d.mean_relative, d.hausdorff_relative);
                            }
                        });
                        level_lines.push_back("\n| level | triangles | Metro mean | mean / diagonal | Hausdorff / diagonal |\n"
                                              "|---|---|---|---|---|\n" + e.out);
                    }
                }
                fs::remove(asset);
            }
        }
        std::printf("\n");
        for (const std::string& l : level_lines) std::printf("%s\n", l.c_str());

        std::printf("\n## OoCS: lodforge cluster mode vs vtkQuadricClustering (grid %zu on the longest side)\n\n", grid);
        std::printf("| model | method | budget MB | seconds (end to end) | M tris/s | peak RSS MB | triangles | Metro mean / diag | "
                    "Hausdorff / diag |\n|---|---|---|---|---|---|---|---|---|\n");
        for (const Model& m : models) {
            std::string dims;
            for (int budget : budgets) {
                const std::string out = tmp.file("oocs.ply");
                const ChildRun r = run_cli({"octree", "build", m.path, "-o", out, "--mode", "cluster", "--grid",
                                            std::to_string(grid), "--memory", std::to_string(budget), "--temp-dir", tmp.path()});
                if (r.exit_code != 0) throw Error(Error::Kind::io, "cluster build failed: " + r.out);
                const std::size_t g = r.out.find("grid ");
                dims = r.out.substr(g + 5, r.out.find(',', g) - g - 5);
                const double tris = number_after(r.out, "-> ");
                std::string metro = "| – | – |";
                if (m.metro && budget == budgets.back()) {
                    const ChildRun e = run_child([&](FILE* w) {
                        const DistanceResult d = compare(read_ply(m.path), read_ply(out), metro_params(samples));
                        std::fprintf(w, "| %.3g | %.3g |", d.mean_relative, d.hausdorff_relative);
                    });
                    metro = e.out;
                }
                std::printf("| %s | **lodforge** OoCS (soup + 1 pass) | %d | %.2f | %.2f | %.0f | %.0f %s\n", m.label.c_str(), budget,
                            r.wall, static_cast<double>(m.triangles) / 1e6 / r.wall, static_cast<double>(r.peak_kb) / 1024.0,
                            tris, metro.c_str());
                std::fflush(stdout);
                fs::remove(out);
            }
#ifdef LODFORGE_BENCH_HAVE_VTK
            unsigned d[3] = {0, 0, 0};
            std::sscanf(dims.c_str(), "%u x %u x %u", &d[0], &d[1], &d[2]);
            const ChildRun v = run_child([&](FILE* w) {
                const Clock::time_point t0 = Clock::now();
                const Mesh in = read_ply(m.path);
                vtkNew<vtkPoints> pts;
                pts->SetDataTypeToFloat();
                pts->SetNumberOfPoints(static_cast<vtkIdType>(in.vertex_count()));
                for (std::size_t i = 0; i < in.vertex_count(); ++i)
                    pts->SetPoint(static_cast<vtkIdType>(i), in.positions[i].x, in.positions[i].y, in.positions[i].z);
                vtkNew<vtkCellArray> cells;
                cells->AllocateExact(static_cast<vtkIdType>(in.triangle_count()), static_cast<vtkIdType>(in.indices.size()));
                for (std::size_t f = 0; f < in.triangle_count(); ++f) {
                    const vtkIdType ids[3] = {in.indices[3 * f], in.indices[3 * f + 1], in.indices[3 * f + 2]};
                    cells->InsertNextCell(3, ids);
                }
                vtkNew<vtkPolyData> pd;
                pd->SetPoints(pts);
                pd->SetPolys(cells);
                const double load = std::chrono::duration<double>(Clock::now() - t0).count();
                const Clock::time_point t1 = Clock::now();
                vtkNew<vtkQuadricClustering> qc;
                qc->SetInputData(pd);
                qc->SetNumberOfDivisions(static_cast<int>(d[0]), static_cast<int>(d[1]), static_cast<int>(d[2]));
                qc->AutoAdjustNumberOfDivisionsOff();
                qc->UseInputPointsOff();
                qc->Update();
                const double filter = std::chrono::duration<double>(Clock::now() - t1).count();
                vtkPolyData* o = qc->GetOutput();
                Mesh om;
                for (vtkIdType i = 0; i < o->GetNumberOfPoints(); ++i) {
                    double p[3];
                    o->GetPoint(i, p);
                    om.positions.push_back({static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
                }
                vtkCellArray* polys = o->GetPolys();
                polys->InitTraversal();
                vtkIdType npts = 0;
                const vtkIdType* ids = nullptr;
                while (polys->GetNextCell(npts, ids))
                    if (npts == 3)
                        for (int k = 0; k < 3; ++k) om.indices.push_back(static_cast<std::uint32_t>(ids[k]));
                std::string metro = "| – | – |";
                if (m.metro) {
                    const DistanceResult dr = compare(in, om, metro_params(samples));
                    char buf[64];
                    std::snprintf(buf, sizeof buf, "| %.3g | %.3g |", dr.mean_relative, dr.hausdorff_relative);
                    metro = buf;
                }
                std::fprintf(w, "%.3f %.3f %zu %s", load, filter, om.triangle_count(), metro.c_str());
            });
            if (v.exit_code == 0) {
                double load = 0, filter = 0;
                std::size_t tris = 0;
                char metro[128] = {};
                std::sscanf(v.out.c_str(), "%lf %lf %zu %127[^\n]", &load, &filter, &tris, metro);
                std::printf("| %s | vtkQuadricClustering (in core: read %.2f s + filter %.2f s), divisions %s | – | %.2f | %.2f | %.0f | %zu %s\n",
                            m.label.c_str(), load, filter, dims.c_str(), load + filter,
                            static_cast<double>(m.triangles) / 1e6 / (load + filter), static_cast<double>(v.peak_kb) / 1024.0, tris,
                            metro);
                std::printf("| | vtkQuadricClustering filter alone | – | %.2f | %.2f | | | | |\n", filter,
                            static_cast<double>(m.triangles) / 1e6 / filter);
            } else {
                std::printf("| %s | vtkQuadricClustering failed (exit %d) | | | | | | | |\n", m.label.c_str(), v.exit_code);
            }
#endif
        }
        std::printf("\nDocument (000, 2.4 GHz P4, 12 MB working memory): Happy Buddha 1,087,716 triangles, octree build 5:39–8:30 "
                    "(3.2–2.1 K tris/s); dragon 871,414, build 4:42–21:44; leaf simplification dragon → 425,531 in 0:37, Buddha → "
                    "527,338 in 0:55 (Metro mean 1.0e-5), → 106,993 in 4:51 (1.7e-4); OoCS on the Buddha → 95,340 in 7:37.\n\n");
        print_load("at the end");
    } catch (const Error& e) {
        std::fprintf(stderr, "lodforge_bench_octree: %s\n", e.what());
        return 1;
    }
    return 0;
}
