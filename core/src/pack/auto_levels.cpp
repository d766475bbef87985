// Automatic LOD chains (auto_levels.h). The ladder of one level per halving of the on-screen size is
// the usual engine spacing (one level per doubling of distance; Luebke et al., "Level of Detail for 3D
// Graphics", 2003, ch. 4), and each rung's error bound is the screen-space tolerance at the size it
// takes over. The levels come from the generalized-quadric collapse chain (Garland & Heckbert 1998,
// Hoppe 1999) and are measured with Metro (Cignoni, Rocchini & Scopigno 1998).
#include "lodforge/pack/auto_levels.h"

#include "lodforge/error.h"
#include "lodforge/simplify/lod_chain.h"

#include <cmath>

namespace lodforge {

std::vector<double> auto_level_sizes(const SwitchParams& switching, double min_screen_pixels) {
    std::vector<double> sizes;
    for (double d = switching.height; d >= min_screen_pixels || sizes.empty(); d /= 2) sizes.push_back(d);
    return sizes;
}

AutoLevelsResult choose_auto_levels(const Mesh& mesh, const AutoLevelsParams& params, Progress* progress) {
    if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, params.source_path, "the mesh has no triangles");
    AutoLevelsResult out;
    // A level that errs by e (of the diagonal) shows e * D pixels when the sphere spans D pixels.
    std::vector<float> errors;
    for (double d : auto_level_sizes(params.switching, params.min_screen_pixels)) {
        const double e = params.switching.pixels / d;
        if (e >= 1) break;  // an error as large as the object: nothing left to simplify towards
        out.candidates.push_back({.screen_pixels = d, .error_target = e});
        errors.push_back(static_cast<float>(e));
    }
    if (errors.empty())
        throw_error(Error::Kind::invalid, params.source_path,
                    "automatic levels: the pixel tolerance is as large as the screen; no level to make");
    LodChainParams p;
    p.levels = lod_levels_from_errors(errors);
    p.simplify.weights = params.weights;
    p.simplify.lock_border = params.lock_border;
    p.measure = true;
    p.distance = params.distance;
    p.distance.vertex_errors = false;
    const LodChainResult chain = build_lod_chain(mesh, p, progress);

    // Fine to coarse, a candidate is kept when it has at most max_kept_ratio of the triangles of the
    // level kept before it (less saves too little for a switch and its bytes). The coarsest candidate
    // that still switches in at min_screen_pixels is kept in any case, as it serves the smallest
    // sizes; kept levels too close above it give way to it.
    const auto tri = [&](std::size_t i) { return double(out.candidates[i].triangles); };
    const auto halves = [&](std::size_t i, const std::vector<std::size_t>& kept) {
        const double before = kept.empty() ? double(mesh.triangle_count()) : tri(kept.back());
        return tri(i) <= params.max_kept_ratio * before;
    };
    std::vector<std::size_t> kept;
    std::size_t usable = 0;  // candidates that still switch in at min_screen_pixels or larger
    for (std::size_t i = 0; i < out.candidates.size(); ++i) {
        AutoLevelCandidate& c = out.candidates[i];
        const LodLevel& level = chain.levels[i + 1];
        c.triangles = level.triangles;
        c.error_relative = level.distance.hausdorff_relative;
        // Where this level may take over (its error is `pixels` there): below the minimum size the
        // chain has gone far enough, and so has every coarser candidate (and one with no triangles left).
        const double takes_over = c.error_relative > 0 ? params.switching.pixels / c.error_relative : INFINITY;
        if (takes_over < params.min_screen_pixels || c.triangles == 0) break;
        usable = i + 1;
        if (halves(i, kept)) kept.push_back(i);
    }
    if (usable > 0 && (kept.empty() || kept.back() != usable - 1)) {
        const std::size_t last = usable - 1;
        while (!kept.empty() && !halves(last, kept)) kept.pop_back();
        if (halves(last, kept)) kept.push_back(last);
    }
    for (std::size_t i : kept) {
        out.candidates[i].kept = true;
        out.targets.push_back({.kind = LodTarget::Kind::triangles, .value = tri(i)});
    }
    if (out.targets.empty())
        throw_error(Error::Kind::invalid, params.source_path,
                    "automatic levels: no level at least halves the triangles within the pixel tolerance down to " +
                        std::to_string(params.min_screen_pixels) + " pixels (" +
                        std::to_string(mesh.triangle_count()) + " triangles); give the levels instead");
    return out;
}

}  // namespace lodforge
