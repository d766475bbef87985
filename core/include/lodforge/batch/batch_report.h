// The outcome of a batch: one record per asset, written as the batch's JSON report and kept in its
// state file (docs/batch.md has the format). `lodforge batch` and the Dask runner write the same records.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lodforge {

struct BatchLevel {
    std::size_t triangles = 0, vertices = 0;
    double error_relative = 0;   // measured Hausdorff distance to the input / bounding-box diagonal
};

struct BatchRecord {
    enum class Status {
        ok,         // the pack was written
        failed,     // the pack was not written: `message` says why (the input, a crash, a timeout)
        skipped,    // unchanged since a successful run (state file): the earlier run's levels and files
        cancelled,  // the batch was stopped before this asset finished; nothing was written
    };
    std::string input, preset, output;   // as BatchAsset
    Status status = Status::failed;
    // What the pack depends on: a re-run skips the asset when all three are unchanged.
    std::string input_sha256, preset_sha256, lodforge_version;
    std::vector<BatchLevel> levels;      // levels[0] = the input
    std::vector<std::string> files;      // relative to output (pack.json included)
    std::vector<std::string> notes;      // the pack's notes (targets a method could not meet, ...)
    std::uint64_t bytes = 0;             // total size of `files`
    double seconds = 0;                  // wall time of the pack run (of the earlier run when skipped)
    std::string message;                 // failed or cancelled: why, for a human
};

std::string_view to_string(BatchRecord::Status status);

struct BatchReport {
    std::string lodforge_version;
    unsigned jobs = 1;
    double seconds = 0;      // wall time of the whole batch
    bool cancelled = false;  // stopped by a signal; the records say which assets finished
    std::vector<BatchRecord> assets;
};

std::string batch_report_json(const BatchReport& report);
// Throws Error(format) naming `source` for text that is not a report as batch_report_json writes it.
BatchReport parse_batch_report(std::string_view json_text, const std::string& source);

// Exchanged inside batch_state.cpp and batch_report.cpp; one JSON shape for a record in both files.
std::string batch_record_json(const BatchRecord& record);
BatchRecord parse_batch_record(std::string_view json_text, const std::string& source);

}  // namespace lodforge
