// Paint files (docs/formats/paint.md): JSON, since the studio writes them beside a preset and people read
// them; a paint of a million vertices is a few megabytes, read once per run.
#include "lodforge/io/vertex_paint.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/io/file_hash.h"
#include "lodforge/io/input_file.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <string_view>

namespace lodforge {
namespace {

constexpr std::string_view kFormat = "lodforge-paint";
constexpr int kVersion = 1;

}  // namespace

VertexPaint read_vertex_paint(const std::string& path, const std::string& mesh_sha256, std::size_t vertex_count) {
    const std::string text = read_input_text(path, "a paint file");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw_error(Error::Kind::format, path, std::string("not a paint file (malformed JSON: ") + e.what() + ")");
    }
    if (!j.is_object() || !j.contains("format") || j["format"] != kFormat)
        throw_error(Error::Kind::format, path, "not a paint file (\"format\" must be \"lodforge-paint\")");
    if (!j.contains("version") || j["version"] != kVersion)
        throw_error(Error::Kind::format, path, "unsupported paint file version (this build reads version 1)");
    for (const auto& [key, value] : j.items())
        if (key != "format" && key != "version" && key != "mesh_sha256" && key != "vertex_count" &&
            key != "importance" && key != "lock")
            throw_error(Error::Kind::format, path, "unknown key '" + key + "'");
    if (!j.contains("mesh_sha256") || !j["mesh_sha256"].is_string() || j["mesh_sha256"] != mesh_sha256)
        throw_error(Error::Kind::invalid, path,
                    "was painted on another mesh (its mesh_sha256 is not the input's " + mesh_sha256 + ")");
    if (!j.contains("vertex_count") || !j["vertex_count"].is_number_unsigned() ||
        j["vertex_count"].get<std::uint64_t>() != vertex_count)
        throw_error(Error::Kind::invalid, path,
                    "was painted on " + (j.contains("vertex_count") ? j["vertex_count"].dump() : std::string("?")) +
                        " vertices; the mesh has " + std::to_string(vertex_count));
    VertexPaint paint;
    if (j.contains("importance")) {
        const auto& a = j["importance"];
        if (!a.is_array() || a.size() != vertex_count)
            throw_error(Error::Kind::invalid, path,
                        "\"importance\" must be an array of " + std::to_string(vertex_count) + " numbers");
        paint.importance.resize(vertex_count);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            const double x = a[v].is_number() ? a[v].get<double>() : std::nan("");
            if (!(x >= 0.0 && x <= 1.0))
                throw_error(Error::Kind::invalid, path,
                            "importance of vertex " + std::to_string(v) + " is " + a[v].dump() + ", not a number in [0, 1]");
            paint.importance[v] = static_cast<float>(x);
        }
    }
    if (j.contains("lock")) {
        const auto& a = j["lock"];
        if (!a.is_array()) throw_error(Error::Kind::invalid, path, "\"lock\" must be an array of vertex indices");
        paint.lock.assign(vertex_count, 0);
        for (const auto& x : a) {
            if (!x.is_number_unsigned() || x.get<std::uint64_t>() >= vertex_count)
                throw_error(Error::Kind::invalid, path,
                            "locked vertex " + x.dump() + " is not a vertex index below " + std::to_string(vertex_count));
            paint.lock[x.get<std::size_t>()] = 1;
        }
    }
    return paint;
}

void write_vertex_paint(const std::string& path, const VertexPaint& paint, const std::string& mesh_sha256,
                        std::size_t vertex_count) {
    if ((!paint.importance.empty() && paint.importance.size() != vertex_count) ||
        (!paint.lock.empty() && paint.lock.size() != vertex_count))
        throw Error(Error::Kind::argument, "write_vertex_paint: masks must have one value per vertex");
    nlohmann::ordered_json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    j["mesh_sha256"] = mesh_sha256;
    j["vertex_count"] = vertex_count;
    if (!paint.importance.empty()) j["importance"] = paint.importance;
    if (!paint.lock.empty()) {
        auto& a = j["lock"] = nlohmann::ordered_json::array();
        for (std::size_t v = 0; v < paint.lock.size(); ++v)
            if (paint.lock[v]) a.push_back(v);
    }
    AtomicFile f(path, false);
    f.stream() << j.dump() << '\n';
    f.commit();
}

void read_paint_sources(const std::string& importance, const std::string& lock, const Mesh& mesh,
                        const std::string& mesh_path, std::vector<float>& importance_out,
                        std::vector<std::uint8_t>& lock_out) {
    std::string hash;
    auto paint = [&](const std::string& file) {
        if (hash.empty()) hash = sha256_file(mesh_path);
        return read_vertex_paint(file, hash, mesh.vertex_count());
    };
    if (importance.rfind("color:", 0) == 0 || importance.rfind("colour:", 0) == 0) {
        const std::string channel = importance.substr(importance.find(':') + 1);
        const int c = channel == "r" ? 0 : channel == "g" ? 1 : channel == "b" ? 2 : channel == "a" ? 3 : -1;
        if (c < 0)
            throw Error(Error::Kind::argument, "importance '" + importance + "': the channel must be r, g, b or a");
        if (!mesh.has_colors())
            throw_error(Error::Kind::invalid, mesh_path, "has no vertex colours to read importance '" + importance + "' from");
        importance_out.resize(mesh.vertex_count());
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            const float x = (&mesh.colors[v].x)[c];
            // Readers give colours in [0, 1]; a file may still hold a NaN.
            if (!(x >= 0.f && x <= 1.f))
                throw_error(Error::Kind::invalid, mesh_path,
                            "vertex " + std::to_string(v) + " has colour channel " + channel + " " + std::to_string(x) +
                                ", outside [0, 1]");
            importance_out[v] = x;
        }
    } else if (!importance.empty()) {
        VertexPaint p = paint(importance);
        if (p.importance.empty()) throw_error(Error::Kind::invalid, importance, "holds no importance");
        importance_out = std::move(p.importance);
    }
    if (!lock.empty()) {
        VertexPaint p = paint(lock);
        if (p.lock.empty()) throw_error(Error::Kind::invalid, lock, "holds no lock");
        lock_out = std::move(p.lock);
    }
}

}  // namespace lodforge
