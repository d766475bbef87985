#include "lodforge/io/input_file.h"

#include "lodforge/error.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace lodforge {

void check_input_file(const std::string& path, std::string_view kind) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status)) throw_error(Error::Kind::io, path, "no such file");
    if (fs::is_directory(status)) throw_error(Error::Kind::io, path, "is a directory, not " + std::string(kind));
    if (!fs::is_regular_file(status))
        throw_error(Error::Kind::io, path, "is not a regular file (a pipe, device or socket); give " +
                                               std::string(kind) + " on disk");
}

std::string read_input_text(const std::string& path, std::string_view kind) {
    check_input_file(path, kind);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open " + std::string(kind) + " for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    return text.str();
}

}  // namespace lodforge
