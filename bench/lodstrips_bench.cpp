// LODStrips benchmark: storage against the indexed mesh, extraction cost per collapse (linear test of
// 1,000 LOD changes as in Ramos 2008 §4.4, and random jumps), build time. Comparators: the document's
// table (docs/benchmarks.md puts them side by side) and, in this run, rebuilding the index buffer of a
// level from the collapse sequence (replay_collapses), which is what an engine does without LODStrips.
//
//   lodforge_bench_lodstrips [--models bunny,dragon2,dragon,frag] [--reps N] [--degenerate] [--max-strip-length N]
//   lodforge_bench_lodstrips --load FILE.lodstrips     (the runtime alone, three rounds)
//   lodforge_bench_lodstrips --save DIR                 (also writes DIR/<model>.lodstrips, for --load)

#include "bench_util.h"
#include "lodforge/error.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/io/mesh_io.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <time.h>

using namespace lodforge;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Extraction is timed in this thread's CPU time: the machine is shared (load 8-9 on 2 cores while these
// numbers were taken), and wall time then mostly measures the other processes.
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Model {
    std::string key, label, path;
};

using lodforge::bench::split;

using lodforge::bench::median;

// ns per collapse over `reps` runs of: 0 -> K in 1,000 equal steps and back (2,000 LOD changes).
double linear_test(lodstrips::LodStrips& rt, int reps, std::size_t& per_change) {
    const std::size_t K = rt.collapse_count();
    per_change = K / 1000;
    std::vector<double> ns;
    volatile std::uint32_t sink = 0;
    for (int r = 0; r < reps; ++r) {
        rt.go_to_level(0);
        const double t0 = cpu_seconds();
        for (std::size_t i = 1; i <= 1000; ++i) {
            rt.go_to_level(K * i / 1000);
            sink = sink + rt.indices()[0];
        }
        for (std::size_t i = 1000; i-- > 0;) {
            rt.go_to_level(K * i / 1000);
            sink = sink + rt.indices()[0];
        }
        rt.clear_changes();
        ns.push_back((cpu_seconds() - t0) * 1e9 / double(2 * K));
    }
    return median(ns);
}

// What an engine adds per LOD change of the linear test: changes() (the spans to upload) and clear_changes(),
// in microseconds per change (the runtime collects the spans from the records when asked). Timed as the
// difference between the forward half of the linear test with and without them (a clock read per change
// would cost as much as what it measures).
double changes_cost(lodstrips::LodStrips& rt, int reps) {
    const std::size_t K = rt.collapse_count();
    std::vector<double> us;
    volatile std::size_t sink = 0;
    auto pass = [&](bool with_changes) {
        rt.go_to_level(0);
        rt.clear_changes();
        const double t0 = cpu_seconds();
        for (std::size_t i = 1; i <= 1000; ++i) {
            rt.go_to_level(K * i / 1000);
            if (with_changes) {
                sink = sink + rt.changes().size();
                rt.clear_changes();
            }
        }
        return cpu_seconds() - t0;
    };
    for (int r = 0; r < reps; ++r) {
        const double without = pass(false);
        const double with = pass(true);
        us.push_back((with - without) * 1e6 / 1000.0);
    }
    return median(us);
}

double random_test(lodstrips::LodStrips& rt, int reps, double& mean_jump) {
    const std::size_t K = rt.collapse_count();
    std::mt19937 rng(42);
    std::vector<std::size_t> targets(1000);
    for (auto& t : targets) t = std::uniform_int_distribution<std::size_t>(0, K)(rng);
    std::size_t moved = 0, at = 0;
    for (std::size_t t : targets) {
        moved += t > at ? t - at : at - t;
        at = t;
    }
    mean_jump = double(moved) / double(targets.size());
    std::vector<double> ns;
    for (int r = 0; r < reps; ++r) {
        rt.go_to_level(0);
        const double t0 = cpu_seconds();
        for (std::size_t t : targets) rt.go_to_level(t);
        rt.clear_changes();
        ns.push_back((cpu_seconds() - t0) * 1e9 / double(moved));
    }
    return median(ns);
}

}  // namespace

int main(int argc, char** argv) {
    std::string models_arg = "bunny,dragon2,dragon,frag";
    int reps = 5;
    bool degenerate = false;
    std::size_t max_strip_length = LodStripsParams{}.max_strip_length;
    std::string load, save;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--models" && i + 1 < argc) models_arg = argv[++i];
        else if (a == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (a == "--degenerate") degenerate = true;
        else if (a == "--load" && i + 1 < argc) load = argv[++i];
        else if (a == "--save" && i + 1 < argc) save = argv[++i];
        else if (a == "--max-strip-length" && i + 1 < argc) max_strip_length = std::size_t(std::atol(argv[++i]));
        else {
            std::fprintf(stderr, "usage: %s [--models bunny,dragon2,dragon,frag] [--reps N] [--degenerate] [--max-strip-length N] [--load FILE] [--save DIR]\n", argv[0]);
            return 2;
        }
    }
    if (!load.empty()) {  // the runtime alone on a written file (for quick A/B runs of the runtime)
        try {
            lodstrips::LodStrips rt;
            std::string why;
            if (!rt.assign(read_lodstrips(load), &why)) throw Error(Error::Kind::invalid, why);
            std::size_t per_change = 0;
            double mean_jump = 0;
            for (int r = 0; r < 3; ++r) {
                const double linear = linear_test(rt, reps, per_change);
                const double jump = random_test(rt, reps, mean_jump);
                const double ch = changes_cost(rt, reps);
                std::printf("%s: linear %.1f ns/collapse (%zu per change), random %.1f ns/collapse, changes() %.2f us/change\n",
                            load.c_str(), linear, per_change, jump, ch);
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "lodforge_bench_lodstrips: %s\n", e.what());
            return 1;
        }
        return 0;
    }
    const std::string data = LODFORGE_SHARED_DATA;
    const std::vector<Model> all = {
        {"bunny", "bunny (69,451 T)", data + "/scan-bunny/bun_zipper.ply"},
        {"dragon2", "dragon res2 (202,520 T)", data + "/scan-dragon/dragon_vrip_res2.ply"},
        {"dragon", "dragon (871,414 T)", data + "/scan-dragon/dragon_vrip.ply"},
        {"frag", "frag_115 (127,229 T, normals + RGB)", data + "/color-open3d-frag115/frag_115.ply"},
    };
    std::printf("LODStrips, %s joins, coarsest level 1%% of the input, strip pieces <= %zu indices, %d reps\n",
                degenerate ? "degenerate" : "restart", max_strip_length, reps);
    std::printf("%-36s %8s %8s %7s %9s %9s %7s | %8s %8s %10s | %8s %8s | %10s\n", "model", "V", "T", "strips",
                "collapses", "MB", "ratio", "build s", "simpl s", "linear ns", "jump ns", "jump avg", "rebuild us");
    try {
        for (const std::string& key : split(models_arg)) {
            const auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
            if (it == all.end()) throw Error(Error::Kind::argument, "unknown model " + key);
            const Mesh mesh = read_mesh(it->path);
            LodStripsParams p;
            p.join = degenerate ? StripJoin::degenerate : StripJoin::restart;
            p.max_strip_length = max_strip_length;
            SimplifyParams sp;
            sp.target_ratio = p.coarsest_ratio;
            auto t0 = Clock::now();
            const SimplifyResult s = simplify(mesh, sp);
            const double simplify_s = seconds_since(t0);
            t0 = Clock::now();
            const LodStripsBuild b = build_lodstrips(mesh, p);
            const double build_s = seconds_since(t0);
            const LodStripsStorage st = lodstrips_storage(b.data);
            if (!save.empty()) write_lodstrips(b.data, save + "/" + key + (degenerate ? "-degenerate" : "") + ".lodstrips");
            lodstrips::LodStrips rt;
            std::string why;
            if (!rt.assign(b.data, &why)) throw Error(Error::Kind::invalid, why);
            std::size_t per_change = 0;
            const double linear = linear_test(rt, reps, per_change);
            double mean_jump = 0;
            const double jump = random_test(rt, reps, mean_jump);
            const double changes_us = changes_cost(rt, reps);
            // Comparator: rebuild the level's index buffer from the collapse sequence.
            std::vector<double> rebuild;
            for (int r = 0; r < 5; ++r) {
                t0 = Clock::now();
                const auto idx = replay_collapses(mesh, b.simplification, b.simplification.collapses.size() / 2);
                rebuild.push_back(seconds_since(t0) * 1e6);
                if (idx.empty()) std::printf("?");
            }
            std::printf("%-36s %8u %8u %7zu %9zu %9.2f %7.3f | %8.2f %8.2f %10.1f | %8.1f %8.0f | %10.0f\n",
                        it->label.c_str(), b.data.vertex_count, b.data.triangles[0], b.data.strip_count(),
                        b.data.collapse_count(), double(st.file_bytes) / 1e6, st.ratio_to_indexed, build_s, simplify_s,
                        linear, jump, mean_jump, median(rebuild));
            std::printf("    changes(): %.2f us per linear-test change\n", changes_us);
            std::printf("    bytes: vertices %zu, strips %zu, changes %zu (%.2f B/collapse); indexed mesh %zu; "
                        "linear test %zu collapses per change; %zu type-1 and %zu type-2 removals\n",
                        st.vertex_bytes, st.strip_bytes, st.change_bytes,
                        double(st.change_bytes) / double(std::max<std::size_t>(1, b.data.collapse_count())),
                        st.indexed_mesh_bytes, per_change, b.degenerate_runs_type1, b.degenerate_runs_type2);
            std::fflush(stdout);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lodforge_bench_lodstrips: %s\n", e.what());
        return 1;
    }
    return 0;
}
