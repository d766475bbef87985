// Runs a batch: each asset is one `lodforge pack` child process, `jobs` of them at a time, so a crash,
// a hang (per-asset timeout) or an out-of-memory kill of one asset fails that asset only. Children
// write their packs through a staging directory (lod_pack.h), so a stopped or killed pack leaves
// nothing in place of its output.
//
//   BatchRunParams p;  p.assets = batch_assets({"scans/", "default", "packs/"});
//   p.pack_command = {"/usr/bin/lodforge", "--quiet", "pack"};  p.jobs = 8;
//   BatchReport r = run_batch(p, &progress);
#pragma once

#include "lodforge/batch/batch_manifest.h"
#include "lodforge/batch/batch_report.h"
#include "lodforge/batch/batch_state.h"
#include "lodforge/progress.h"

#include <functional>
#include <string>
#include <vector>

namespace lodforge {

struct BatchRunParams {
    std::vector<BatchAsset> assets;
    // Assets up to date in this state are skipped (batch_state.h); null: every asset runs.
    const BatchState* state = nullptr;
    unsigned jobs = 0;               // child processes at a time; 0: one per hardware thread
    double timeout_seconds = 0;      // per asset, then SIGTERM (and SIGKILL 10 s later); 0: none
    // The argv that runs one pack, before "INPUT [--preset P] -o OUTPUT --json" (lodforge pack's
    // options and its --json output); argv[0] is a path.
    std::vector<std::string> pack_command;
    std::string lodforge_version;    // goes into each record's fingerprint
    // Called (on the calling thread) with each asset's final record as it comes: the state can be
    // saved while the batch runs.
    std::function<void(const BatchRecord&)> on_record;
};

// One record per asset, in the order of `assets`. A cancel (progress->cancelled()) stops the children
// (SIGTERM), waits for them and returns with report.cancelled set: the assets not finished are
// `cancelled`. Throws Error(argument) for an empty pack_command; everything an asset can do wrong is
// in its record.
BatchReport run_batch(const BatchRunParams& params, Progress* progress = nullptr);

}  // namespace lodforge
