// A batch's memory between runs: for each asset (keyed by its output directory) the record of its last
// run, with the content hashes it was built from. A re-run skips an asset whose input bytes, preset
// content and LodForge version are unchanged and whose last run succeeded (its pack.json still there);
// failures are retried. The file is replaced atomically, so a killed batch leaves the last good state.
#pragma once

#include "lodforge/batch/batch_manifest.h"
#include "lodforge/batch/batch_report.h"

#include <map>
#include <string>

namespace lodforge {

struct BatchState {
    std::map<std::string, BatchRecord> assets;   // output directory -> its last ok or failed record
};

// An empty state when `path` does not exist; throws Error(format) naming the file when it is not a state
// file, Error(io) when it cannot be read.
BatchState load_batch_state(const std::string& path);
void save_batch_state(const std::string& path, const BatchState& state);   // atomic write

// What an asset's pack depends on, filled into a record's input/preset/output and hashes. Throws
// Error naming the file when the input is not a readable regular file or the preset cannot be loaded.
BatchRecord batch_fingerprint(const BatchAsset& asset, const std::string& lodforge_version);

// The state's record for `fingerprint`'s asset when the asset can be skipped (see above), else null.
const BatchRecord* up_to_date_record(const BatchState& state, const BatchRecord& fingerprint);

// Stores the outcome of a run (ok or failed); skipped and cancelled records leave the state as it was.
void record_outcome(BatchState& state, const BatchRecord& record);

}  // namespace lodforge
