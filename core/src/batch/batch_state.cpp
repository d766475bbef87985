#include "lodforge/batch/batch_state.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/io/file_hash.h"
#include "lodforge/io/input_file.h"
#include "lodforge/pack/preset_library.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace lodforge {
namespace {
using Json = nlohmann::ordered_json;
constexpr int kStateVersion = 1;
}  // namespace

BatchState load_batch_state(const std::string& path) {
    BatchState state;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return state;
    const std::string text = read_input_text(path, "a batch state file");
    Json j;
    try {
        j = Json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw_error(Error::Kind::format, path, std::string("not valid JSON: ") + e.what());
    }
    if (!j.is_object() || j.value("format", "") != "lodforge-batch-state")
        throw_error(Error::Kind::format, path,
                    "not a LodForge batch state file (no \"format\": \"lodforge-batch-state\"); give another --state");
    if (j.value("version", 0) != kStateVersion)
        throw_error(Error::Kind::format, path, "batch state version " + j.value("version", Json()).dump() + " is not 1");
    if (!j.contains("assets") || !j["assets"].is_object())
        throw_error(Error::Kind::format, path, "no \"assets\" object");
    for (const auto& [output, record] : j["assets"].items()) {
        BatchRecord r = parse_batch_record(record.dump(), path);
        if (r.output != output) throw_error(Error::Kind::format, path, "asset \"" + output + "\" names another output");
        state.assets.emplace(output, std::move(r));
    }
    return state;
}

void save_batch_state(const std::string& path, const BatchState& state) {
    Json j;
    j["format"] = "lodforge-batch-state";
    j["version"] = kStateVersion;
    Json assets = Json::object();
    for (const auto& [output, record] : state.assets) assets[output] = Json::parse(batch_record_json(record));
    j["assets"] = assets;
    AtomicFile file(path, false);
    file.stream() << j.dump(1) << "\n";
    file.commit();
}

BatchRecord batch_fingerprint(const BatchAsset& asset, const std::string& lodforge_version) {
    BatchRecord r;
    r.input = asset.input;
    r.preset = asset.preset;
    r.output = asset.output;
    r.lodforge_version = lodforge_version;
    check_input_file(asset.input, "a mesh file");
    r.input_sha256 = sha256_file(asset.input);
    // The preset's content, not its name: an edited preset file (or a shipped preset changed by an
    // upgrade) rebuilds its assets. Its canonical JSON ignores formatting and key order.
    r.preset_sha256 = sha256_text(preset_to_json(asset.preset.empty() ? Preset{} : resolve_preset(asset.preset)));
    return r;
}

const BatchRecord* up_to_date_record(const BatchState& state, const BatchRecord& fingerprint) {
    const auto it = state.assets.find(fingerprint.output);
    if (it == state.assets.end()) return nullptr;
    const BatchRecord& last = it->second;
    std::error_code ec;
    const bool unchanged = last.status == BatchRecord::Status::ok && last.input == fingerprint.input &&
                           last.input_sha256 == fingerprint.input_sha256 &&
                           last.preset_sha256 == fingerprint.preset_sha256 &&
                           last.lodforge_version == fingerprint.lodforge_version;
    // A pack deleted since (or never moved into place) is built again.
    return unchanged && std::filesystem::exists(std::filesystem::path(last.output) / "pack.json", ec) ? &last : nullptr;
}

void record_outcome(BatchState& state, const BatchRecord& record) {
    if (record.status == BatchRecord::Status::ok || record.status == BatchRecord::Status::failed)
        state.assets.insert_or_assign(record.output, record);
}

}  // namespace lodforge
