#include "lodforge/batch/batch_manifest.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"
#include "lodforge/io/mesh_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace lodforge {
namespace {
namespace fs = std::filesystem;

bool is_preset_file(const std::string& preset) {
    // The rule of resolve_preset (preset_library.h): a '/' or ".json" makes it a file.
    return preset.find('/') != std::string::npos || (preset.size() >= 5 && preset.ends_with(".json"));
}

std::string absolute_from(const fs::path& base, const std::string& path) {
    const fs::path p(path);
    return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

std::string preset_from(const fs::path& base, const std::string& preset) {
    return is_preset_file(preset) ? absolute_from(base, preset) : preset;
}

bool is_manifest(const fs::path& source) {
    const std::string ext = source.extension().string();
    return ext == ".json" || ext == ".csv";
}

// A manifest row before its paths are resolved; `where` names it in messages ("line 3", "entry 2").
struct Row {
    std::string input, preset, output, where;
};

std::vector<Row> json_rows(const std::string& path, const std::string& text) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw_error(Error::Kind::format, path, std::string("not valid JSON: ") + e.what());
    }
    if (j.is_object()) {
        for (const auto& [key, value] : j.items())
            if (key != "assets")
                throw_error(Error::Kind::format, path, "unknown key \"" + key + "\" (a manifest has \"assets\")");
        if (!j.contains("assets")) throw_error(Error::Kind::format, path, "no \"assets\" list");
        j = j["assets"];
    }
    if (!j.is_array()) throw_error(Error::Kind::format, path, "a manifest is a list of assets or {\"assets\": [...]}");
    std::vector<Row> rows;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string where = "entry " + std::to_string(i + 1);
        const nlohmann::json& e = j[i];
        if (!e.is_object()) throw_error(Error::Kind::format, path, where + " is not an object");
        Row row;
        row.where = where;
        for (const auto& [key, value] : e.items()) {
            std::string* field = key == "input" ? &row.input : key == "preset" ? &row.preset
                                                             : key == "output" ? &row.output : nullptr;
            if (!field)
                throw_error(Error::Kind::format, path,
                            where + ": unknown key \"" + key + "\" (keys: input, preset, output)");
            if (!value.is_string()) throw_error(Error::Kind::format, path, where + ": \"" + key + "\" is not a string");
            *field = value.get<std::string>();
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

// One CSV record (RFC 4180 without line breaks inside quotes).
std::vector<std::string> csv_fields(const std::string& line, const std::string& path, const std::string& where) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c != '"') fields.back() += c;
            else if (i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
            else quoted = false;
        } else if (c == '"' && fields.back().empty()) {
            quoted = true;
        } else if (c == ',') {
            fields.emplace_back();
        } else {
            fields.back() += c;
        }
    }
    if (quoted) throw_error(Error::Kind::format, path, where + ": a quoted field is not closed");
    return fields;
}

std::vector<Row> csv_rows(const std::string& path, const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::vector<std::string> header;
    std::vector<Row> rows;
    for (int number = 1; std::getline(in, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos) continue;
        const std::string where = "line " + std::to_string(number);
        std::vector<std::string> fields = csv_fields(line, path, where);
        if (header.empty()) {
            header = fields;
            for (const std::string& name : header)
                if (name != "input" && name != "preset" && name != "output")
                    throw_error(Error::Kind::format, path,
                                where + ": unknown column \"" + name + "\" (the header names input, preset, output)");
            if (std::find(header.begin(), header.end(), "input") == header.end())
                throw_error(Error::Kind::format, path, where + ": the header has no \"input\" column");
            continue;
        }
        if (fields.size() != header.size())
            throw_error(Error::Kind::format, path,
                        where + ": " + std::to_string(fields.size()) + " fields, the header has " +
                            std::to_string(header.size()));
        Row row;
        row.where = where;
        for (std::size_t k = 0; k < header.size(); ++k)
            (header[k] == "input" ? row.input : header[k] == "preset" ? row.preset : row.output) = fields[k];
        rows.push_back(std::move(row));
    }
    if (header.empty()) throw_error(Error::Kind::format, path, "empty manifest (no header line)");
    return rows;
}

std::vector<BatchAsset> manifest_assets(const BatchSourceParams& params, const fs::path& manifest) {
    const std::string path = manifest.string();
    const std::string text = read_input_text(path, "a manifest file");
    const std::vector<Row> rows = manifest.extension() == ".json" ? json_rows(path, text) : csv_rows(path, text);

    const fs::path base = fs::absolute(manifest).parent_path();
    const fs::path root = batch_output_root(params);
    const std::string default_preset = params.preset.empty() ? "" : preset_from(fs::current_path(), params.preset);
    std::vector<BatchAsset> assets;
    std::map<std::string, std::string> seen;  // output -> the row that claimed it
    for (const Row& row : rows) {
        if (row.input.empty()) throw_error(Error::Kind::format, path, row.where + ": no input");
        BatchAsset a;
        a.input = absolute_from(base, row.input);
        a.preset = row.preset.empty() ? default_preset : preset_from(base, row.preset);
        a.output = row.output.empty() ? (root / fs::path(a.input).stem()).lexically_normal().string()
                                      : absolute_from(base, row.output);
        if (const auto [it, fresh] = seen.emplace(a.output, row.where); !fresh)
            throw_error(Error::Kind::format, path,
                        row.where + ": output " + a.output + " is also " + it->second +
                            "'s (give each asset its own \"output\")");
        assets.push_back(std::move(a));
    }
    return assets;
}

std::vector<BatchAsset> directory_assets(const BatchSourceParams& params, const fs::path& dir) {
    const fs::path root = batch_output_root(params);
    const fs::path base = fs::absolute(dir).lexically_normal();
    std::vector<fs::path> inputs;
    std::error_code ec;
    fs::recursive_directory_iterator it(base, fs::directory_options::skip_permission_denied, ec);
    if (ec) throw_error(Error::Kind::io, dir.string(), "cannot list the directory: " + ec.message());
    for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (ec) throw_error(Error::Kind::io, dir.string(), "cannot list the directory: " + ec.message());
        const fs::path p = it->path().lexically_normal();
        // Packs written into the tree being scanned contain .glb files: never treat them as inputs.
        if (it->is_directory() && (p == root || p.filename().string().starts_with("."))) {
            it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() && format_from_extension(p.string()) != FileFormat::unknown) inputs.push_back(p);
    }
    std::sort(inputs.begin(), inputs.end());
    std::map<fs::path, int> stems;  // folder/stem -> number of inputs
    for (const fs::path& p : inputs) ++stems[p.parent_path() / p.stem()];
    const std::string preset = params.preset.empty() ? "" : preset_from(fs::current_path(), params.preset);
    std::vector<BatchAsset> assets;
    for (const fs::path& p : inputs) {
        std::string name = p.stem().string();
        if (stems[p.parent_path() / p.stem()] > 1) name += "-" + p.extension().string().substr(1);
        const fs::path relative = p.parent_path().lexically_relative(base);
        assets.push_back({p.string(), preset, (root / relative / name).lexically_normal().string()});
    }
    return assets;
}

}  // namespace

std::string batch_output_root(const BatchSourceParams& params) {
    if (!params.output_root.empty()) return fs::absolute(params.output_root).lexically_normal().string();
    fs::path source = fs::absolute(params.source).lexically_normal();
    if (!source.has_filename()) source = source.parent_path();  // "dir/" names dir
    if (is_manifest(source) && !fs::is_directory(source)) return source.parent_path().string();
    return source.string() + "-packs";
}

std::vector<BatchAsset> batch_assets(const BatchSourceParams& params) {
    const fs::path source(params.source);
    std::error_code ec;
    const fs::file_status status = fs::status(source, ec);
    if (!fs::exists(status)) throw_error(Error::Kind::io, params.source, "no such file or directory");
    if (fs::is_directory(status)) return directory_assets(params, source);
    if (!is_manifest(source))
        throw_error(Error::Kind::format, params.source,
                    "not a directory or a manifest (a manifest is a .json or .csv file, docs/batch.md)");
    return manifest_assets(params, source);
}

}  // namespace lodforge
