#include "lodforge/batch/batch_report.h"

#include "lodforge/error.h"

#include <nlohmann/json.hpp>

namespace lodforge {
namespace {
using Json = nlohmann::ordered_json;

constexpr int kReportVersion = 1;

Json record_to_json(const BatchRecord& r) {
    Json j;
    j["input"] = r.input;
    j["preset"] = r.preset;
    j["output"] = r.output;
    j["status"] = std::string(to_string(r.status));
    j["message"] = r.message.empty() ? Json(nullptr) : Json(r.message);
    j["input_sha256"] = r.input_sha256;
    j["preset_sha256"] = r.preset_sha256;
    j["lodforge_version"] = r.lodforge_version;
    Json levels = Json::array();
    for (const BatchLevel& l : r.levels)
        levels.push_back({{"triangles", l.triangles}, {"vertices", l.vertices}, {"error_relative", l.error_relative}});
    j["levels"] = levels;
    j["files"] = r.files;
    j["notes"] = r.notes;
    j["bytes"] = r.bytes;
    j["seconds"] = r.seconds;
    return j;
}

BatchRecord::Status status_from(const std::string& name, const std::string& source) {
    for (auto s : {BatchRecord::Status::ok, BatchRecord::Status::failed, BatchRecord::Status::skipped,
                   BatchRecord::Status::cancelled})
        if (to_string(s) == name) return s;
    throw_error(Error::Kind::format, source, "unknown asset status \"" + name + "\"");
}

BatchRecord record_from_json(const Json& j, const std::string& source) {
    try {
        BatchRecord r;
        r.input = j.at("input").get<std::string>();
        r.preset = j.at("preset").get<std::string>();
        r.output = j.at("output").get<std::string>();
        r.status = status_from(j.at("status").get<std::string>(), source);
        if (!j.at("message").is_null()) r.message = j.at("message").get<std::string>();
        r.input_sha256 = j.at("input_sha256").get<std::string>();
        r.preset_sha256 = j.at("preset_sha256").get<std::string>();
        r.lodforge_version = j.at("lodforge_version").get<std::string>();
        for (const Json& l : j.at("levels"))
            r.levels.push_back({l.at("triangles").get<std::size_t>(), l.at("vertices").get<std::size_t>(),
                                l.at("error_relative").get<double>()});
        r.files = j.at("files").get<std::vector<std::string>>();
        r.notes = j.at("notes").get<std::vector<std::string>>();
        r.bytes = j.at("bytes").get<std::uint64_t>();
        r.seconds = j.at("seconds").get<double>();
        return r;
    } catch (const nlohmann::json::exception& e) {
        throw_error(Error::Kind::format, source, std::string("not a batch asset record: ") + e.what());
    }
}

Json parse_json(std::string_view text, const std::string& source) {
    try {
        return Json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw_error(Error::Kind::format, source, std::string("not valid JSON: ") + e.what());
    }
}

}  // namespace

std::string_view to_string(BatchRecord::Status status) {
    switch (status) {
        case BatchRecord::Status::ok: return "ok";
        case BatchRecord::Status::failed: return "failed";
        case BatchRecord::Status::skipped: return "skipped";
        case BatchRecord::Status::cancelled: return "cancelled";
    }
    return "failed";
}

std::string batch_record_json(const BatchRecord& record) { return record_to_json(record).dump(); }

BatchRecord parse_batch_record(std::string_view json_text, const std::string& source) {
    return record_from_json(parse_json(json_text, source), source);
}

std::string batch_report_json(const BatchReport& report) {
    Json j;
    j["format"] = "lodforge-batch-report";
    j["version"] = kReportVersion;
    j["lodforge_version"] = report.lodforge_version;
    j["jobs"] = report.jobs;
    j["seconds"] = report.seconds;
    j["cancelled"] = report.cancelled;
    Json summary = {{"assets", report.assets.size()}};
    for (auto s : {BatchRecord::Status::ok, BatchRecord::Status::failed, BatchRecord::Status::skipped,
                   BatchRecord::Status::cancelled}) {
        std::size_t n = 0;
        for (const BatchRecord& r : report.assets) n += r.status == s;
        summary[std::string(to_string(s))] = n;
    }
    j["summary"] = summary;
    Json assets = Json::array();
    for (const BatchRecord& r : report.assets) assets.push_back(record_to_json(r));
    j["assets"] = assets;
    return j.dump(2) + "\n";
}

BatchReport parse_batch_report(std::string_view json_text, const std::string& source) {
    const Json j = parse_json(json_text, source);
    if (!j.is_object() || j.value("format", "") != "lodforge-batch-report")
        throw_error(Error::Kind::format, source, "not a LodForge batch report (no \"format\": \"lodforge-batch-report\")");
    try {
        if (j.at("version").get<int>() != kReportVersion)
            throw_error(Error::Kind::format, source, "batch report version " + j.at("version").dump() + " is not 1");
        BatchReport report;
        report.lodforge_version = j.at("lodforge_version").get<std::string>();
        report.jobs = j.at("jobs").get<unsigned>();
        report.seconds = j.at("seconds").get<double>();
        report.cancelled = j.at("cancelled").get<bool>();
        for (const Json& a : j.at("assets")) report.assets.push_back(record_from_json(a, source));
        return report;
    } catch (const nlohmann::json::exception& e) {
        throw_error(Error::Kind::format, source, std::string("not a batch report: ") + e.what());
    }
}

}  // namespace lodforge
