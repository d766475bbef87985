// PLY read benchmark: LodForge's reader against vtkPLYReader and OpenMesh::IO::read_mesh, in one run.
//
// At start the ASCII dragon (../shared/data/scan-dragon/dragon_vrip.ply) is converted with write_ply to
// binary little endian in a temporary directory. Then every reader reads each file several times,
// interleaved (so machine noise hits all of them alike); the table shows the median and best time,
// MB/s, million triangles/s, and each reader's median relative to LodForge's.
//
//   lodforge_bench_ply_read [mesh.ply] [--reps N]

#include "lodforge/error.h"
#include "lodforge/io/ply.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#ifdef LODFORGE_BENCH_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPolyData.h>
#endif
#ifdef LODFORGE_BENCH_HAVE_OPENMESH
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh types: registers the readers
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#endif

namespace fs = std::filesystem;

namespace {

struct Reader {
    std::string name;
    std::function<std::size_t(const std::string&)> read;  // returns triangles read
};

struct Row {
    std::string file, reader;
    double median = 0, best = 0, megabytes = 0;
    std::size_t triangles = 0;
};

std::vector<Reader> readers() {
    std::vector<Reader> r;
    r.push_back({"lodforge read_ply", [](const std::string& p) { return lodforge::read_ply(p).triangle_count(); }});
    r.push_back({"lodforge PlyReader (64K chunks)", [](const std::string& p) {
                     // The streaming path the out-of-core builder uses: fixed buffers, no Mesh.
                     lodforge::PlyReader reader(p);
                     std::vector<lodforge::Vec3f> positions(1 << 16);
                     lodforge::PlyFaceChunk faces;
                     std::size_t triangles = 0;
                     while (reader.current_element()) {
                         if (reader.at_vertices()) {
                             reader.read_vertices(positions);
                         } else if (reader.at_faces()) {
                             faces.clear();
                             reader.read_faces(1 << 16, faces);
                             triangles += faces.triangle_count();
                         } else {
                             reader.skip_element();
                         }
                     }
                     return triangles;
                 }});
#ifdef LODFORGE_BENCH_HAVE_VTK
    r.push_back({"vtkPLYReader", [](const std::string& p) {
                     vtkNew<vtkPLYReader> reader;
                     reader->SetFileName(p.c_str());
                     reader->Update();
                     return static_cast<std::size_t>(reader->GetOutput()->GetNumberOfPolys());
                 }});
#endif
#ifdef LODFORGE_BENCH_HAVE_OPENMESH
    r.push_back({"OpenMesh read_mesh", [](const std::string& p) {
                     OpenMesh::TriMesh_ArrayKernelT<> mesh;
                     if (!OpenMesh::IO::read_mesh(mesh, p)) return std::size_t(0);
                     return static_cast<std::size_t>(mesh.n_faces());
                 }});
#endif
    return r;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    std::string source = LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip.ply";
    int reps = 5;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else source = a;
    }
    try {
        const fs::path tmp = fs::temp_directory_path() / ("lodforge-bench-ply-" + std::to_string(::getpid()));
        fs::create_directories(tmp);
        const std::string binary = (tmp / "dragon_binary_le.ply").string();
        const std::string ascii = (tmp / "dragon_ascii.ply").string();
        {
            const lodforge::Mesh mesh = lodforge::read_ply(source);
            lodforge::WriteOptions o;
            o.ply_encoding = lodforge::PlyEncoding::binary_little_endian;
            lodforge::write_ply(mesh, binary, o);
            fs::copy_file(source, ascii, fs::copy_options::overwrite_existing);  // same page-cache footing
            std::printf("source %s: %zu vertices, %zu triangles\n", source.c_str(), mesh.vertex_count(),
                        mesh.triangle_count());
        }

        const std::vector<Reader> all = readers();
        std::vector<Row> rows;
        for (const std::string& file : {binary, ascii}) {
            const double mb = static_cast<double>(fs::file_size(file)) / 1e6;
            std::vector<std::vector<double>> times(all.size());
            std::vector<std::size_t> tris(all.size());
            for (std::size_t i = 0; i < all.size(); ++i) tris[i] = all[i].read(file);  // warm the cache
            for (int rep = 0; rep < reps; ++rep)
                for (std::size_t i = 0; i < all.size(); ++i) {
                    const auto t0 = std::chrono::steady_clock::now();
                    tris[i] = all[i].read(file);
                    times[i].push_back(seconds_since(t0));
                }
            for (std::size_t i = 0; i < all.size(); ++i) {
                std::sort(times[i].begin(), times[i].end());
                rows.push_back({file == binary ? "binary LE" : "ASCII", all[i].name, times[i][times[i].size() / 2],
                                times[i].front(), mb, tris[i]});
            }
        }
        fs::remove_all(tmp);

        std::printf("\n%-10s %-32s %9s %9s %8s %10s %12s %14s\n", "file", "reader", "median s", "best s", "MB/s",
                    "Mtris/s", "triangles", "vs lodforge");
        double base = 0;
        for (const Row& r : rows) {
            if (r.reader == "lodforge read_ply") base = r.median;
            std::printf("%-10s %-32s %9.3f %9.3f %8.1f %10.2f %12zu %13.2fx\n", r.file.c_str(), r.reader.c_str(),
                        r.median, r.best, r.megabytes / r.median, static_cast<double>(r.triangles) / r.median / 1e6,
                        r.triangles, r.median / base);
        }
        std::printf("\n(%d timed reps per reader and file, interleaved; 'vs lodforge' = median / lodforge read_ply median)\n",
                    reps);
    } catch (const lodforge::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
