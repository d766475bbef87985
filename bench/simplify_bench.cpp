// Simplification benchmark: LodForge's simplify() (geometry only and attribute-aware) against
// meshoptimizer's meshopt_simplify, OpenMesh's Decimater with ModQuadric and vtkQuadricDecimation, in one run.
//
// Every method simplifies each model to 50 %, 10 % and 1 % of its triangles. Printed per run: seconds
// (CPU time of the simplification call alone: no file reading, no conversion into the comparator's mesh type),
// million input triangles per second, the triangles reached, and the Metro-style error of lodforge's
// compare() against the input: symmetric Hausdorff (max) and mean distance relative to the input's
// bounding-box diagonal, and colour RMS (0-255) where the input has colours.
//
//   lodforge_bench_simplify [--quick] [--models dragon,bunny,frag,duck,bottle] [--ratios 0.5,0.1,0.01]
//                           [--reps N] [--samples N] [--no-vtk] [--no-openmesh] [--openmesh-dragon-all]
//                           [--greedy] [--no-attributes] [--digest] [--area-weight area|sqrt] [--height-weight W]
//
// --quick: dragon and bunny at 10 % only, without OpenMesh. OpenMesh runs on the full dragon at 10 % only
// (it takes ~20 s per level) unless --openmesh-dragon-all. With --reps N > 1 the time is the median of N
// runs of each method (errors are measured on the last run). --greedy adds lodforge's heap schedule
// (SimplifyParams::Schedule::greedy, the engine before the round schedule) as a method. --no-attributes
// leaves out the attribute-aware run (geometry-only profiles). --digest adds, for lodforge's runs, a 64-bit
// FNV-1a hash of the result (output indices, positions, vertex map, collapse sequence, error bits): two
// builds that print the same digests produced the same simplifications (for checking exact changes).

#include "bench_util.h"
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/simplify/simplify.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#ifdef LODFORGE_BENCH_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>
#endif
#ifdef LODFORGE_BENCH_HAVE_OPENMESH
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#endif

using namespace lodforge;

namespace {

// CPU time of the process (all methods run single-threaded): the machine is shared, so wall time mostly
// measures the other jobs.
struct Clock {
    using duration = std::chrono::duration<double>;
    struct time_point {
        double s;
        duration operator-(const time_point& o) const { return duration(s - o.s); }
    };
    static time_point now() {
        timespec t{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return {double(t.tv_sec) + 1e-9 * double(t.tv_nsec)};
    }
};

struct Model {
    std::string key, label, path;
};

struct Outcome {
    Mesh mesh;          // the simplified mesh, with the attributes the method carries
    double seconds = 0;
    std::uint64_t digest = 0;  // lodforge only: hash of the whole result (--digest)
};

// FNV-1a over the bytes of everything simplify() returns that a change could alter.
std::uint64_t digest_of(const SimplifyResult& r) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    auto bytes = [&](const void* data, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    };
    auto vec = [&](const auto& v) { bytes(v.data(), v.size() * sizeof(v[0])); };
    vec(r.mesh.indices);
    vec(r.mesh.positions);
    vec(r.vertex_map);
    vec(r.collapses);
    vec(r.moves);
    bytes(&r.error, sizeof r.error);
    const int reason = static_cast<int>(r.reason);
    bytes(&reason, sizeof reason);
    return h;
}

using lodforge::bench::split;

// The input's faces on a vertex subset (methods that keep input vertices: meshopt, OpenMesh).
Mesh with_indices(const Mesh& in, std::vector<std::uint32_t> indices) {
    Mesh m;
    m.positions = in.positions;
    m.normals = in.normals;
    m.colors = in.colors;
    m.texcoords = in.texcoords;
    m.indices = std::move(indices);
    return m;
}

// --area-weight / --height-weight: lodforge's opt-in order terms (docs/simplification.md, "Hausdorff against
// meshopt"), for every lodforge method of the run.
struct OrderOptions {
    SimplifyParams::AreaWeight area_weight = SimplifyParams::AreaWeight::area;
    float height_weight = 0.f;
};
OrderOptions g_order;

Outcome run_lodforge(const Mesh& in, float ratio, bool attributes,
                     SimplifyParams::Schedule schedule = SimplifyParams::Schedule::passes) {
    SimplifyParams p;
    p.target_ratio = ratio;
    p.schedule = schedule;
    p.area_weight = g_order.area_weight;
    p.height_weight = g_order.height_weight;
    if (!attributes) {
        p.weights.normal = 0;
        p.weights.color = 0;
        p.weights.texcoord = 0;
    }
    const auto t0 = Clock::now();
    SimplifyResult r = simplify(in, p);
    Outcome o;
    o.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    o.digest = digest_of(r);
    o.mesh = std::move(r.mesh);
    return o;
}

Outcome run_meshopt(const Mesh& in, float ratio) {
    std::vector<std::uint32_t> dst(in.indices.size());
    const std::size_t target = static_cast<std::size_t>(double(in.triangle_count()) * ratio) * 3;
    const auto t0 = Clock::now();
    float err = 0;
    const std::size_t n = meshopt_simplify(dst.data(), in.indices.data(), in.indices.size(), &in.positions[0].x,
                                           in.vertex_count(), sizeof(Vec3f), target, 1e30f, 0, &err);
    Outcome o;
    o.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    dst.resize(n);
    o.mesh = with_indices(in, std::move(dst));
    return o;
}

#ifdef LODFORGE_BENCH_HAVE_OPENMESH
Outcome run_openmesh(const Mesh& in, float ratio) {
    using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
    OMesh om;
    std::vector<OMesh::VertexHandle> vh(in.vertex_count());
    for (std::size_t i = 0; i < in.vertex_count(); ++i)
        vh[i] = om.add_vertex(OMesh::Point(in.positions[i].x, in.positions[i].y, in.positions[i].z));
    for (std::size_t f = 0; f < in.triangle_count(); ++f)  // complex edges are refused (as read_mesh does)
        om.add_face(vh[in.indices[3 * f]], vh[in.indices[3 * f + 1]], vh[in.indices[3 * f + 2]]);
    const std::size_t target = static_cast<std::size_t>(double(in.triangle_count()) * ratio);
    const auto t0 = Clock::now();
    OpenMesh::Decimater::DecimaterT<OMesh> dec(om);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle mod;
    dec.add(mod);
    dec.module(mod).unset_max_err();
    dec.initialize();
    dec.decimate_to_faces(0, target);
    Outcome o;
    o.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    // Half-edge collapses: surviving vertices keep their handles, i.e. their input index.
    std::vector<std::uint32_t> idx;
    for (auto f : om.faces()) {
        if (om.status(f).deleted()) continue;
        for (auto v : om.fv_range(f)) idx.push_back(static_cast<std::uint32_t>(v.idx()));
    }
    o.mesh = with_indices(in, std::move(idx));
    return o;
}
#endif

#ifdef LODFORGE_BENCH_HAVE_VTK
Outcome run_vtk(const Mesh& in, float ratio, bool attributes) {
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToFloat();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(in.vertex_count()));
    for (std::size_t i = 0; i < in.vertex_count(); ++i)
        pts->SetPoint(static_cast<vtkIdType>(i), in.positions[i].x, in.positions[i].y, in.positions[i].z);
    vtkNew<vtkCellArray> cells;
    for (std::size_t f = 0; f < in.triangle_count(); ++f) {
        const vtkIdType ids[3] = {in.indices[3 * f], in.indices[3 * f + 1], in.indices[3 * f + 2]};
        cells->InsertNextCell(3, ids);
    }
    vtkNew<vtkPolyData> pd;
    pd->SetPoints(pts);
    pd->SetPolys(cells);
    if (attributes && in.has_colors()) {
        vtkNew<vtkFloatArray> c;
        c->SetNumberOfComponents(3);
        c->SetNumberOfTuples(static_cast<vtkIdType>(in.vertex_count()));
        for (std::size_t i = 0; i < in.vertex_count(); ++i)
            c->SetTuple3(static_cast<vtkIdType>(i), in.colors[i].x, in.colors[i].y, in.colors[i].z);
        pd->GetPointData()->SetScalars(c);
    }
    if (attributes && in.has_normals()) {
        vtkNew<vtkFloatArray> n;
        n->SetNumberOfComponents(3);
        n->SetNumberOfTuples(static_cast<vtkIdType>(in.vertex_count()));
        for (std::size_t i = 0; i < in.vertex_count(); ++i)
            n->SetTuple3(static_cast<vtkIdType>(i), in.normals[i].x, in.normals[i].y, in.normals[i].z);
        pd->GetPointData()->SetNormals(n);
    }
    vtkNew<vtkQuadricDecimation> dec;
    dec->SetInputData(pd);
    dec->SetTargetReduction(1.0 - double(ratio));
    if (attributes) {
        dec->AttributeErrorMetricOn();
        dec->SetScalarsAttribute(in.has_colors());
        dec->SetNormalsAttribute(in.has_normals());
        dec->SetTCoordsAttribute(false);
        dec->SetVectorsAttribute(false);
        dec->SetTensorsAttribute(false);
    }
    const auto t0 = Clock::now();
    dec->Update();
    Outcome o;
    o.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    vtkPolyData* out = dec->GetOutput();
    Mesh& m = o.mesh;
    m.positions.resize(static_cast<std::size_t>(out->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
        double p[3];
        out->GetPoint(i, p);
        m.positions[static_cast<std::size_t>(i)] = {float(p[0]), float(p[1]), float(p[2])};
    }
    vtkDataArray* sc = out->GetPointData()->GetScalars();
    if (attributes && in.has_colors() && sc && sc->GetNumberOfComponents() == 3) {
        m.colors.resize(m.positions.size());
        for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
            const double* c = sc->GetTuple3(i);
            m.colors[static_cast<std::size_t>(i)] = {float(c[0]), float(c[1]), float(c[2]), 1.f};
        }
    }
    vtkCellArray* polys = out->GetPolys();
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
        if (npts == 3)
            for (int k = 0; k < 3; ++k) m.indices.push_back(static_cast<std::uint32_t>(ids[k]));
    return o;
}
#endif

using lodforge::bench::median;

}  // namespace

int main(int argc, char** argv) {
    const std::string data = LODFORGE_SHARED_DATA;
    std::vector<Model> all = {
        {"dragon", "dragon_vrip (871K)", data + "/scan-dragon/dragon_vrip.ply"},
        {"bunny", "bun_zipper (70K)", data + "/scan-bunny/bun_zipper.ply"},
        {"frag", "frag_115 (normals+RGB)", data + "/color-open3d-frag115/frag_115.ply"},
        {"duck", "Duck.gltf (UV)", data + "/tex-duck/glTF/Duck.gltf"},
        {"bottle", "WaterBottle.gltf (UV+N)", data + "/tex-water-bottle/WaterBottle.gltf"},
    };
    std::vector<std::string> models = {"dragon", "bunny", "frag", "duck", "bottle"};
    std::vector<float> ratios = {0.5f, 0.1f, 0.01f};
    int reps = 1;
    std::size_t samples = 0;
    bool vtk = true, openmesh = true, openmesh_dragon_all = false, greedy = false, attributes = true, digest = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return bench::option_value(argc, argv, i); };
        if (a == "--quick") {
            models = {"dragon", "bunny"};
            ratios = {0.1f};
            openmesh = false;
        } else if (a == "--models") {
            models = split(next());
        } else if (a == "--ratios") {
            ratios.clear();
            for (const std::string& r : split(next())) ratios.push_back(std::stof(r));
        } else if (a == "--reps") {
            reps = std::max(1, std::atoi(next().c_str()));
        } else if (a == "--samples") {
            samples = static_cast<std::size_t>(std::atoll(next().c_str()));
        } else if (a == "--no-vtk") {
            vtk = false;
        } else if (a == "--no-openmesh") {
            openmesh = false;
        } else if (a == "--greedy") {
            greedy = true;
        } else if (a == "--no-attributes") {
            attributes = false;
        } else if (a == "--digest") {
            digest = true;
        } else if (a == "--openmesh-dragon-all") {
            openmesh_dragon_all = true;
        } else if (a == "--area-weight") {
            const std::string v = next();
            if (v != "area" && v != "sqrt") {
                std::fprintf(stderr, "--area-weight: area or sqrt, got %s\n", v.c_str());
                return 2;
            }
            g_order.area_weight = v == "sqrt" ? SimplifyParams::AreaWeight::sqrt_area : SimplifyParams::AreaWeight::area;
        } else if (a == "--height-weight") {
            g_order.height_weight = static_cast<float>(std::atof(next().c_str()));
        } else {
            std::fprintf(stderr,
                         "usage: %s [--quick] [--models dragon,bunny,frag,duck,bottle] [--ratios 0.5,0.1,0.01] "
                         "[--reps N] [--samples N] [--no-vtk] [--no-openmesh] [--openmesh-dragon-all] [--greedy] "
                         "[--no-attributes] [--digest] [--area-weight area|sqrt] [--height-weight W]\n",
                         argv[0]);
            return 2;
        }
    }

    std::printf("%-24s %6s %-30s %9s %8s %9s %8s %9s %9s %7s\n", "model", "ratio", "method", "seconds", "ratio",
                "Mtris/s", "tris", "max", "mean", "colRMS");
    for (const std::string& key : models) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
        if (it == all.end()) {
            std::fprintf(stderr, "unknown model %s\n", key.c_str());
            return 2;
        }
        Mesh in;
        try {
            in = read_mesh(it->path);
        } catch (const Error& e) {
            std::fprintf(stderr, "%s: %s\n", it->path.c_str(), e.what());
            return 1;
        }
        const bool has_attributes = attributes && (in.has_normals() || in.has_colors() || in.has_texcoords());
        for (float r : ratios) {
            struct Method {
                std::string name;
                std::function<Outcome()> run;
            };
            std::vector<Method> methods;
            methods.push_back({"lodforge geometry", [&] { return run_lodforge(in, r, false); }});
            if (has_attributes) methods.push_back({"lodforge attributes", [&] { return run_lodforge(in, r, true); }});
            if (greedy)
                methods.push_back({"lodforge geometry, greedy heap", [&] {
                                       return run_lodforge(in, r, false, SimplifyParams::Schedule::greedy);
                                   }});
            methods.push_back({"meshopt_simplify 0.18", [&] { return run_meshopt(in, r); }});
#ifdef LODFORGE_BENCH_HAVE_OPENMESH
            if (openmesh && (key != "dragon" || r == 0.1f || openmesh_dragon_all))
                methods.push_back({"OpenMesh ModQuadric", [&] { return run_openmesh(in, r); }});
#endif
#ifdef LODFORGE_BENCH_HAVE_VTK
            if (vtk) {
                methods.push_back({"vtkQuadricDecimation", [&] { return run_vtk(in, r, false); }});
                if (in.has_colors())
                    methods.push_back({"vtkQuadricDecimation attr", [&] { return run_vtk(in, r, true); }});
            }
#endif
            double base = 0;
            for (const Method& m : methods) {
                std::vector<double> times;
                Outcome o;
                for (int k = 0; k < reps; ++k) {
                    o = m.run();
                    times.push_back(o.seconds);
                }
                const double t = median(times);
                if (base == 0) base = t;
                DistanceParams dp;
                dp.samples = samples;
                dp.vertex_errors = false;
                const DistanceResult d = compare(in, o.mesh, dp);
                char colour[16] = "-";
                if (d.has_color_error) std::snprintf(colour, sizeof colour, "%.2f", d.color_rms);
                std::printf("%-24s %5.0f%% %-30s %9.4f %7.2fx %9.2f %8zu %9.2e %9.2e %7s", it->label.c_str(),
                            double(r) * 100, m.name.c_str(), t, t / base, double(in.triangle_count()) / t * 1e-6,
                            o.mesh.triangle_count(), d.hausdorff_relative, d.mean_relative, colour);
                if (digest && o.digest != 0) std::printf(" %016llx", static_cast<unsigned long long>(o.digest));
                std::printf("\n");
                std::fflush(stdout);
            }
        }
    }
    return 0;
}
