// What a batch processes: assets, each one input mesh, one preset and one pack directory. A batch comes
// from a directory (every mesh file inside, recursively, with one preset) or a manifest file (JSON or
// CSV, docs/batch.md). Relative paths in a manifest are relative to the manifest's directory, so a
// manifest travels with its assets (a studio's shared storage mounted anywhere).
#pragma once

#include <string>
#include <vector>

namespace lodforge {

struct BatchAsset {
    std::string input;    // mesh file (absolute, lexically normal)
    std::string preset;   // a shipped preset's name or a preset file (absolute); empty: the studio's default
    std::string output;   // pack directory (absolute, lexically normal); the asset's key in state and report
};

struct BatchSourceParams {
    std::string source;        // a directory or a manifest file (.json or .csv)
    std::string preset;        // the preset of a directory's assets and of manifest rows that name none
    std::string output_root;   // where a directory's packs go, and manifest rows without an output;
                               // empty: "<directory>-packs" beside a directory, the manifest's directory
};

// The assets in source order (a directory's in path order). A directory gives, for each .ply, .obj,
// .gltf, .glb file below it (the output root's own tree left out), the pack directory
// output_root/<relative folder>/<stem>; two inputs of one stem in one folder are told apart as
// <stem>-<extension>. Throws Error(io) for a missing or unreadable source, Error(format) naming the
// manifest and the line or entry for a malformed manifest (bad JSON or CSV, unknown key, missing input,
// two assets with one output).
std::vector<BatchAsset> batch_assets(const BatchSourceParams& params);

// The output root that batch_assets uses for `params` (the default above when output_root is empty).
std::string batch_output_root(const BatchSourceParams& params);

}  // namespace lodforge
