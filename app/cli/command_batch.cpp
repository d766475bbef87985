// `lodforge batch`: many packs in one command (docs/batch.md). The runner lives in the core
// (lodforge/batch/); this file turns options into its parameters, keeps the state file and writes the
// report. --plan and --merge are the two halves the Dask runner (python/lodforge/dask_batch.py) calls
// around its per-asset tasks, so the state and report formats have one writer.
#include "commands.h"
#include "terminal_progress.h"

#include "lodforge/batch/batch_run.h"
#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/io/input_file.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace lodforge::cli {
namespace {
namespace fs = std::filesystem;

struct BatchOptions {
    std::string source, preset, output_root, state, report, only, merge;
    unsigned jobs = 0;
    double timeout = 0;
    bool no_state = false, plan = false;
};

void write_text(const std::string& path, const std::string& text) {
    if (path == "-") {
        std::fputs(text.c_str(), stdout);
        return;
    }
    fs::create_directories(fs::absolute(path).parent_path());
    AtomicFile file(path, false);
    file.stream() << text;
    file.commit();
}

void save_state(const std::string& path, const BatchState& state) {
    fs::create_directories(fs::absolute(path).parent_path());
    save_batch_state(path, state);
}

std::string this_executable() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw Error(Error::Kind::io, "batch: cannot find the lodforge executable (/proc/self/exe): " + ec.message());
    return self.string();
}

void print_failure(const BatchRecord& r) {
    if (r.status != BatchRecord::Status::failed) return;
    // Most messages name the input already (the pack's own errors); crashes and timeouts do not.
    const std::string where = r.message.find(r.input) == std::string::npos ? r.input + ": " : "";
    std::fprintf(stderr, "lodforge: failed: %s%s\n", where.c_str(), r.message.c_str());
}

// Prints the summary line and turns failures and a cancel into the exit code (1, 128 + signal).
void conclude(const BatchReport& report, const std::string& report_path, bool quiet_stdout) {
    std::size_t ok = 0, failed = 0, skipped = 0, cancelled = 0;
    for (const BatchRecord& r : report.assets) {
        ok += r.status == BatchRecord::Status::ok;
        failed += r.status == BatchRecord::Status::failed;
        skipped += r.status == BatchRecord::Status::skipped;
        cancelled += r.status == BatchRecord::Status::cancelled;
    }
    const std::string where = report_path == "-" ? "" : "; report: " + report_path;
    if (!quiet_stdout)
        std::printf("batch: %zu assets: %zu ok, %zu failed, %zu skipped (unchanged), %zu cancelled in %.2f s%s\n",
                    report.assets.size(), ok, failed, skipped, cancelled, report.seconds, where.c_str());
    if (report.cancelled)
        throw Error(Error::Kind::cancelled, "batch stopped: " + std::to_string(ok + failed) + " assets finished, " +
                                                std::to_string(cancelled) + " not (no partial pack left)" + where);
    if (failed > 0)
        throw Error(Error::Kind::invalid,
                    std::to_string(failed) + " of " + std::to_string(report.assets.size()) + " assets failed" + where);
}

void run_plan(const std::vector<BatchAsset>& assets, const BatchState& state, const std::string& state_path,
              const std::string& report_path) {
    nlohmann::ordered_json j;
    j["state"] = state_path.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(state_path);
    j["report"] = report_path;
    j["lodforge_version"] = LODFORGE_VERSION;
    j["assets"] = nlohmann::ordered_json::array();
    for (const BatchAsset& a : assets) {
        nlohmann::ordered_json entry = {{"input", a.input}, {"preset", a.preset}, {"output", a.output}};
        const BatchRecord* last = nullptr;
        try {
            last = up_to_date_record(state, batch_fingerprint(a, LODFORGE_VERSION));
        } catch (const Error&) {
            // The asset's own run reports what is wrong with it.
        }
        entry["up_to_date"] = last != nullptr;
        if (last) {
            BatchRecord skipped = *last;
            skipped.status = BatchRecord::Status::skipped;
            entry["record"] = nlohmann::ordered_json::parse(batch_record_json(skipped));
        } else {
            entry["record"] = nullptr;
        }
        j["assets"].push_back(entry);
    }
    std::printf("%s\n", j.dump(2).c_str());
}

}  // namespace

void add_batch_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<BatchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "batch",
        "Pack many meshes: every mesh file of a directory (recursively) with one preset, or the assets of a\n"
        "manifest (JSON or CSV: input, preset, output), in parallel child processes. A state file makes a\n"
        "re-run skip unchanged assets and retry failures; a JSON report lists every asset (docs/batch.md).");
    cmd->footer("Examples:\n"
                "  lodforge batch scans/ --preset mobile -o packs/      every mesh below scans/, one per core at a time\n"
                "  lodforge batch assets.csv --jobs 4 --timeout 600     a manifest; an asset over 10 min fails\n"
                "  lodforge batch assets.json --report - --no-state     rebuild all, report on stdout\n"
                "  python3 -m lodforge.dask_batch assets.json --scheduler tcp://host:8786   the same on Dask");
    cmd->add_option("SOURCE", o->source, "A directory of meshes or a manifest (.json, .csv)")->required();
    cmd->add_option("--preset", o->preset,
                    "Preset (shipped name or file) of a directory's meshes and of manifest rows naming none "
                    "(default: the studio's default)");
    cmd->add_option("-o,--output", o->output_root,
                    "Output root: a directory's packs go to ROOT/<folder>/<stem> (default: SOURCE-packs beside a "
                    "directory, the manifest's folder for a manifest)");
    cmd->add_option("-j,--jobs", o->jobs, "Assets packed at a time (default: one per CPU core)")
        ->check(CLI::Range(1u, 1024u));
    cmd->add_option("--timeout", o->timeout, "Seconds one asset may take before it is stopped and fails (default: none)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--state", o->state, "State file (default: ROOT/batch-state.json)");
    cmd->add_flag("--no-state", o->no_state, "Neither read nor write a state file: every asset runs");
    cmd->add_option("--report", o->report, "JSON report (default: ROOT/batch-report.json; - for stdout)");
    cmd->add_option("--only", o->only, "Run the one asset whose output directory (or input file) this is");
    cmd->add_flag("--plan", o->plan, "Print the assets and which are up to date as JSON; run nothing");
    cmd->add_option("--merge", o->merge,
                    "Record the assets of a report (the Dask runner's results) into the state file and write "
                    "the report; run nothing");
    cmd->get_option("--plan")->excludes("--merge");
    cmd->get_option("--no-state")->excludes("--state");

    cmd->callback([o, &global] {
        const BatchSourceParams source{o->source, o->preset, o->output_root};
        std::vector<BatchAsset> assets = batch_assets(source);
        const std::string root = batch_output_root(source);
        const std::string state_path =
            o->no_state ? "" : o->state.empty() ? (fs::path(root) / "batch-state.json").string() : o->state;
        const std::string report_path = o->report.empty() ? (fs::path(root) / "batch-report.json").string() : o->report;
        if (!o->only.empty()) {
            const std::string key = fs::absolute(o->only).lexically_normal().string();
            std::erase_if(assets, [&](const BatchAsset& a) { return a.output != key && a.input != key; });
            if (assets.empty())
                throw Error(Error::Kind::argument, "batch --only " + o->only + ": no asset of " + o->source +
                                                       " has this output directory or input file");
        }
        BatchState state = state_path.empty() ? BatchState{} : load_batch_state(state_path);

        if (o->plan) {
            run_plan(assets, state, state_path, report_path);
            return;
        }
        if (!o->merge.empty()) {
            BatchReport merged = parse_batch_report(read_input_text(o->merge, "a batch report"), o->merge);
            for (const BatchRecord& r : merged.assets) {
                print_failure(r);
                record_outcome(state, r);
            }
            if (!state_path.empty()) save_state(state_path, state);
            write_text(report_path, batch_report_json(merged));
            conclude(merged, report_path, report_path == "-");
            return;
        }

        BatchRunParams params;
        params.assets = std::move(assets);
        params.state = state_path.empty() ? nullptr : &state;
        params.jobs = o->jobs;
        params.timeout_seconds = o->timeout;
        params.pack_command = {this_executable(), "--quiet", "pack"};
        params.lodforge_version = LODFORGE_VERSION;
        // The state is saved as records come (at most every 2 s), so a batch killed outright keeps
        // most of its work; the state object is read by the runner only before the first child starts.
        BatchState next = state;
        auto last_save = std::chrono::steady_clock::now();
        params.on_record = [&](const BatchRecord& r) {
            print_failure(r);
            record_outcome(next, r);
            if (!state_path.empty() && std::chrono::steady_clock::now() - last_save > std::chrono::seconds(2)) {
                save_state(state_path, next);
                last_save = std::chrono::steady_clock::now();
            }
        };
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const BatchReport report = run_batch(params, &progress);
        progress.finish();
        if (!state_path.empty()) save_state(state_path, next);
        write_text(report_path, batch_report_json(report));
        conclude(report, report_path, report_path == "-");
    });
}

}  // namespace lodforge::cli
