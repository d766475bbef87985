#include "lodforge/batch/batch_run.h"

#include "batch/child_process.h"
#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstring>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <poll.h>
#include <thread>

namespace lodforge {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A child that ignores SIGTERM this long after it was sent is killed.
constexpr auto kKillGrace = std::chrono::seconds(10);

struct Running {
    std::size_t index = 0;
    std::unique_ptr<ChildProcess> child;
    Clock::time_point started, deadline = Clock::time_point::max(), kill_at = Clock::time_point::max();
    bool timed_out = false, stopped = false, killed = false;
};

std::string format_seconds(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", s);
    return text;
}

// The child's own message ("lodforge: error: X" -> "X"), or its last line of stderr.
std::string failure_message(const std::string& err) {
    std::string last;
    std::size_t start = 0;
    while (start < err.size()) {
        std::size_t end = err.find('\n', start);
        if (end == std::string::npos) end = err.size();
        const std::string line = err.substr(start, end - start);
        static const std::string prefix = "lodforge: error: ";
        if (line.starts_with(prefix)) return line.substr(prefix.size());
        if (!line.empty()) last = line;
        start = end + 1;
    }
    return last;
}

void fill_from_pack_json(BatchRecord& r, const std::string& out) {
    const auto j = nlohmann::json::parse(out);
    for (const auto& l : j.at("levels"))
        r.levels.push_back({l.at("triangles").get<std::size_t>(), l.at("vertices").get<std::size_t>(),
                            l.at("error_relative").get<double>()});
    r.files = j.at("files").get<std::vector<std::string>>();
    r.notes = j.at("notes").get<std::vector<std::string>>();
    r.bytes = 0;
    for (const std::string& f : r.files) {
        std::error_code ec;
        const auto size = fs::file_size(fs::path(r.output) / f, ec);
        if (!ec) r.bytes += size;
    }
}

void finish(BatchRecord& r, const Running& run) {
    const ChildProcess& c = *run.child;
    r.seconds = std::chrono::duration<double>(Clock::now() - run.started).count();
    if (run.stopped) {
        r.status = BatchRecord::Status::cancelled;
        r.message = "the batch was stopped before this asset finished";
        return;
    }
    if (c.exit_code() == 0) {
        try {
            fill_from_pack_json(r, c.out());
            r.status = BatchRecord::Status::ok;
            return;
        } catch (const nlohmann::json::exception& e) {
            r.message = std::string("the pack run printed no readable result: ") + e.what();
        }
    } else if (run.timed_out) {
        r.message = "timed out after " + format_seconds(std::chrono::duration<double>(run.deadline - run.started).count()) +
                    " s (stopped; no pack written)";
    } else if (c.term_signal() != 0) {
        r.message = "the pack process crashed (signal " + std::to_string(c.term_signal()) + ", " +
                    strsignal(c.term_signal()) + "); no pack written";
    } else {
        const std::string why = failure_message(c.err());
        r.message = why.empty() ? "the pack process exited with status " + std::to_string(c.exit_code()) : why;
    }
    r.status = BatchRecord::Status::failed;
    r.levels.clear();
    r.files.clear();
}

}  // namespace

BatchReport run_batch(const BatchRunParams& params, Progress* progress) {
    if (params.pack_command.empty()) throw Error(Error::Kind::argument, "run_batch: no pack command");
    const auto batch_start = Clock::now();
    const unsigned jobs = params.jobs > 0 ? params.jobs : std::max(1u, std::thread::hardware_concurrency());
    BatchReport report;
    report.lodforge_version = params.lodforge_version;
    report.jobs = jobs;
    report.assets.resize(params.assets.size());
    const std::size_t total = params.assets.size();
    std::size_t finished = 0;
    auto publish = [&](std::size_t i) {
        ++finished;
        if (params.on_record) params.on_record(report.assets[i]);
        if (progress) progress->report(total ? double(finished) / double(total) : 1.0,
                                       "batch " + std::to_string(finished) + "/" + std::to_string(total) + ": " +
                                           fs::path(params.assets[i].input).filename().string());
    };
    auto cancelled = [&] { return progress && progress->cancelled(); };

    // What each asset depends on, before anything runs: unchanged assets are skipped, unreadable
    // inputs and presets fail here with their message.
    std::deque<std::size_t> queue;
    for (std::size_t i = 0; i < total; ++i) {
        BatchRecord& r = report.assets[i];
        const BatchAsset& a = params.assets[i];
        if (cancelled()) {
            r = BatchRecord{};
            r.input = a.input, r.preset = a.preset, r.output = a.output;
            r.status = BatchRecord::Status::cancelled;
            r.lodforge_version = params.lodforge_version;
            r.message = "the batch was stopped before this asset started";
            continue;
        }
        try {
            r = batch_fingerprint(a, params.lodforge_version);
        } catch (const Error& e) {
            r.input = a.input, r.preset = a.preset, r.output = a.output;
            r.lodforge_version = params.lodforge_version;
            r.status = BatchRecord::Status::failed;
            r.message = e.what();
            publish(i);
            continue;
        }
        if (const BatchRecord* last = params.state ? up_to_date_record(*params.state, r) : nullptr) {
            r = *last;
            r.status = BatchRecord::Status::skipped;
            publish(i);
            continue;
        }
        queue.push_back(i);
    }

    std::vector<Running> running;
    bool stopping = false;
    while (!queue.empty() || !running.empty()) {
        if (!stopping && cancelled()) {
            stopping = true;
            for (Running& r : running) {
                r.stopped = true;
                r.child->signal(SIGTERM);
                r.kill_at = std::min(r.kill_at, Clock::now() + kKillGrace);
            }
            for (std::size_t i : queue) {
                report.assets[i].status = BatchRecord::Status::cancelled;
                report.assets[i].message = "the batch was stopped before this asset started";
            }
            queue.clear();
        }
        while (!stopping && running.size() < jobs && !queue.empty()) {
            const std::size_t i = queue.front();
            queue.pop_front();
            const BatchAsset& a = params.assets[i];
            std::vector<std::string> argv = params.pack_command;
            argv.push_back(a.input);
            if (!a.preset.empty()) argv.insert(argv.end(), {"--preset", a.preset});
            argv.insert(argv.end(), {"-o", a.output, "--json"});
            Running r;
            r.index = i;
            r.started = Clock::now();
            if (params.timeout_seconds > 0)
                r.deadline = r.started + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(params.timeout_seconds));
            try {
                r.child = std::make_unique<ChildProcess>(argv);
            } catch (const Error& e) {
                report.assets[i].status = BatchRecord::Status::failed;
                report.assets[i].message = e.what();
                publish(i);
                continue;
            }
            running.push_back(std::move(r));
        }

        std::vector<pollfd> fds;
        for (const Running& r : running)
            for (int fd : r.child->open_fds()) fds.push_back({fd, POLLIN, 0});
        // The tick also bounds how late a timeout, a cancel or an exit without output is noticed.
        ::poll(fds.data(), fds.size(), 100);

        const auto now = Clock::now();
        for (std::size_t k = 0; k < running.size();) {
            Running& r = running[k];
            r.child->read_available();
            if (!r.timed_out && now >= r.deadline) {
                r.timed_out = true;
                r.child->signal(SIGTERM);
                r.kill_at = now + kKillGrace;
            }
            if (!r.killed && now >= r.kill_at) {
                r.killed = true;
                r.child->signal(SIGKILL);
            }
            if (!r.child->try_reap()) {
                ++k;
                continue;
            }
            // Ctrl+C reaches the children too (one process group): one that stopped on it before the
            // batch noticed was stopped, not failed.
            if (r.child->exit_code() != 0 && cancelled()) r.stopped = true;
            // A killed pack had no chance to remove its staging directory: do it now.
            if (r.killed) remove_stale_temporaries(fs::path(params.assets[r.index].output).parent_path().string());
            finish(report.assets[r.index], r);
            publish(r.index);
            running.erase(running.begin() + static_cast<std::ptrdiff_t>(k));
        }
    }
    report.cancelled = stopping || cancelled();
    report.seconds = std::chrono::duration<double>(Clock::now() - batch_start).count();
    return report;
}

}  // namespace lodforge
