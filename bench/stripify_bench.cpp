// Stripification benchmark: LodForge's stripify() (restart and degenerate joins) against meshoptimizer's
// meshopt_stripify (file order, and after meshopt_optimizeVertexCacheStrip) and vtkStripper, in one run.
//
// lodforge runs with both triangle orders (StripOrder::run_off, the default, and StripOrder::cache, strips
// grown along meshopt_optimizeVertexCacheStrip's order). Printed per method: indices per triangle of the one buffer to draw (restart / join indices included;
// vtkStripper's strips are counted as if joined by restart indices), number of strips, ACMR of that buffer
// for a FIFO cache of 16 and 32 vertices (lodforge::acmr, the same simulation for every method), seconds
// of the call(s) alone in thread CPU time (median of --reps; no file reading or conversion) and million input
// triangles per second. Every buffer is expanded back to triangles and checked against the input (winding included for
// lodforge and meshoptimizer; vtkStripper is checked as a set of unoriented triangles).
//
//   lodforge_bench_stripify [--models bunny,dragon2,dragon,frag] [--reps N] [--window N] [--no-vtk] [--orders]
//   (--window N overrides the orders' own default window; --orders adds both cache orders alone as triangle lists: optimize_vertex_cache, meshopt_optimizeVertexCacheStrip)

#include "bench_util.h"
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/strips/stripify.h"
#include "lodforge/strips/vertex_cache.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <time.h>

#ifdef LODFORGE_BENCH_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStripper.h>
#endif

using namespace lodforge;

namespace {

using Idx = std::vector<std::uint32_t>;

struct Model {
    std::string key, label, path;
};

using lodforge::bench::split;

using lodforge::bench::median;

// What one method produced: a buffer of the given primitive and its strip count.
struct Output {
    Idx buffer;
    Primitive primitive = Primitive::strip_restart;
    std::size_t strips = 0;
};

// CPU time of this thread: the machine is shared, and wall time then mostly measures the other processes.
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double time_median(int reps, const std::function<Output()>& run, Output& last) {
    std::vector<double> times;
    for (int k = 0; k < reps; ++k) {
        const double t0 = cpu_seconds();
        last = run();
        times.push_back(cpu_seconds() - t0);
    }
    return median(times);
}

std::vector<std::array<std::uint32_t, 3>> triangles_of(const Idx& list, bool oriented) {
    std::vector<std::array<std::uint32_t, 3>> out;
    for (std::size_t i = 0; i + 2 < list.size(); i += 3) {
        std::array<std::uint32_t, 3> t = {list[i], list[i + 1], list[i + 2]};
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        if (oriented) {
            std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        } else {
            std::sort(t.begin(), t.end());
        }
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::size_t count_strips(const Idx& buffer) {
    if (buffer.empty()) return 0;
    return std::size_t(std::count(buffer.begin(), buffer.end(), restart_index)) + 1;
}

#ifdef LODFORGE_BENCH_HAVE_VTK
vtkSmartPointer<vtkPolyData> to_vtk(const Mesh& m) {
    vtkNew<vtkPoints> pts;
    pts->SetNumberOfPoints(vtkIdType(m.vertex_count()));
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        pts->SetPoint(vtkIdType(i), m.positions[i][0], m.positions[i][1], m.positions[i][2]);
    }
    vtkNew<vtkCellArray> polys;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const vtkIdType ids[3] = {m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]};
        polys->InsertNextCell(3, ids);
    }
    auto pd = vtkSmartPointer<vtkPolyData>::New();
    pd->SetPoints(pts);
    pd->SetPolys(polys);
    return pd;
}

// vtkStripper's strips (and any triangle it left as a polygon) joined with restart indices.
Output from_vtk(vtkPolyData* out) {
    Output o;
    auto append = [&](vtkCellArray* cells) {
        vtkIdType npts = 0;
        const vtkIdType* ids = nullptr;
        for (cells->InitTraversal(); cells->GetNextCell(npts, ids);) {
            if (!o.buffer.empty()) o.buffer.push_back(restart_index);
            for (vtkIdType k = 0; k < npts; ++k) o.buffer.push_back(std::uint32_t(ids[k]));
            ++o.strips;
        }
    };
    append(out->GetStrips());
    append(out->GetPolys());
    return o;
}
#endif

}  // namespace

int main(int argc, char** argv) {
    const std::string data = LODFORGE_SHARED_DATA;
    const std::vector<Model> all = {
        {"bunny", "bun_zipper (69K tris)", data + "/scan-bunny/bun_zipper.ply"},
        {"dragon2", "dragon_vrip_res2 (203K)", data + "/scan-dragon/dragon_vrip_res2.ply"},
        {"dragon", "dragon_vrip (871K)", data + "/scan-dragon/dragon_vrip.ply"},
        {"frag", "frag_115 (normals+RGB)", data + "/color-open3d-frag115/frag_115.ply"},
    };
    std::vector<std::string> models = {"bunny", "dragon2", "dragon", "frag"};
    int reps = 3;
    std::size_t window = StripifyParams{}.window;
    bool vtk = true;
    bool orders = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : std::string(); };
        if (a == "--models") {
            models = split(next());
        } else if (a == "--reps") {
            reps = std::max(1, std::atoi(next().c_str()));
        } else if (a == "--window") {
            window = std::size_t(std::atol(next().c_str()));
        } else if (a == "--orders") {
            orders = true;
        } else if (a == "--no-vtk") {
            vtk = false;
        } else {
            std::fprintf(stderr, "usage: %s [--models bunny,dragon2,dragon,frag] [--reps N] [--window N] [--no-vtk] [--orders]\n",
                         argv[0]);
            return 2;
        }
    }
#ifndef LODFORGE_BENCH_HAVE_VTK
    vtk = false;
#endif

    std::printf("| model | method | indices/triangle | strips | ACMR16 | ACMR32 | seconds | M tris/s |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    bool all_exact = true;
    for (const std::string& key : models) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
        if (it == all.end()) {
            std::fprintf(stderr, "unknown model %s\n", key.c_str());
            return 2;
        }
        Mesh mesh;
        try {
            mesh = read_mesh(it->path);
        } catch (const Error& e) {
            std::fprintf(stderr, "%s\n", e.what());
            return 1;
        }
        const std::size_t vc = mesh.vertex_count();
        const Idx& in = mesh.indices;
        const auto expected_oriented = triangles_of(in, true);
        const auto expected_unoriented = triangles_of(in, false);

        auto report = [&](const char* method, double seconds, const Output& o, bool oriented) {
            const Idx tris = expand_strips_to_triangles(o.buffer, o.primitive);
            const bool exact = oriented ? triangles_of(tris, true) == expected_oriented
                                        : triangles_of(tris, false) == expected_unoriented;
            all_exact = all_exact && exact;
            std::printf("| %s | %s%s | %.3f | %zu | %.3f | %.3f | %.4f | %.1f |\n", it->label.c_str(), method,
                        exact ? "" : " (TRIANGLES DIFFER)", indices_per_triangle(o.buffer, o.primitive), o.strips,
                        acmr(o.buffer, vc, 16, o.primitive), acmr(o.buffer, vc, 32, o.primitive), seconds,
                        double(mesh.triangle_count()) / seconds * 1e-6);
            std::fflush(stdout);
        };
        Output o;
        for (StripOrder order : {StripOrder::run_off, StripOrder::cache}) {
            for (StripJoin join : {StripJoin::restart, StripJoin::degenerate}) {
                StripifyParams p;
                p.join = join;
                p.order = order;
                p.window = window;
                const double s = time_median(reps, [&] {
                    StripifyResult r = stripify(mesh, p);
                    return Output{std::move(r.indices),
                                  join == StripJoin::restart ? Primitive::strip_restart : Primitive::strip_degenerate,
                                  r.strips.size()};
                }, o);
                const std::string name = std::string("lodforge stripify, ") +
                                         (order == StripOrder::run_off ? "run_off" : "cache") + " order, " +
                                         (join == StripJoin::restart ? "restart" : "degenerate");
                report(name.c_str(), s, o, true);
            }
        }
        if (orders) {  // the two triangle orders alone, as lists: where the strips' ACMR comes from
            const double s = time_median(reps, [&] {
                Output r;
                r.buffer = optimize_vertex_cache(in, vc, 16);
                r.primitive = Primitive::triangles;
                return r;
            }, o);
            report("lodforge order (list)", s, o, true);
            const double s2 = time_median(reps, [&] {
                Output r;
                r.buffer.resize(in.size());
                meshopt_optimizeVertexCacheStrip(r.buffer.data(), in.data(), in.size(), vc);
                r.primitive = Primitive::triangles;
                return r;
            }, o);
            report("meshopt order (list)", s2, o, true);
        }
        {
            const double s = time_median(reps, [&] {
                Output r;
                r.buffer.resize(meshopt_stripifyBound(in.size()));
                r.buffer.resize(meshopt_stripify(r.buffer.data(), in.data(), in.size(), vc, restart_index));
                r.strips = count_strips(r.buffer);
                return r;
            }, o);
            report("meshopt_stripify, file order", s, o, true);
        }
        {
            Idx ordered(in.size());
            const double s = time_median(reps, [&] {
                meshopt_optimizeVertexCacheStrip(ordered.data(), in.data(), in.size(), vc);
                Output r;
                r.buffer.resize(meshopt_stripifyBound(in.size()));
                r.buffer.resize(meshopt_stripify(r.buffer.data(), ordered.data(), ordered.size(), vc, restart_index));
                r.strips = count_strips(r.buffer);
                return r;
            }, o);
            report("meshopt_optimizeVertexCacheStrip + meshopt_stripify", s, o, true);
        }
#ifdef LODFORGE_BENCH_HAVE_VTK
        if (vtk) {
            const vtkSmartPointer<vtkPolyData> pd = to_vtk(mesh);
            const double s = time_median(reps, [&] {
                vtkNew<vtkStripper> stripper;
                stripper->SetInputData(pd);
                stripper->Update();
                return from_vtk(stripper->GetOutput());
            }, o);
            report("vtkStripper", s, o, false);
        }
#endif
    }
    return all_exact ? 0 : 1;
}
