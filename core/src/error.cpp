#include "lodforge/error.h"

namespace lodforge {

const char* kind_name(Error::Kind kind) noexcept {
    switch (kind) {
    case Error::Kind::io: return "io";
    case Error::Kind::format: return "format";
    case Error::Kind::invalid: return "invalid";
    case Error::Kind::unsupported: return "unsupported";
    case Error::Kind::argument: return "argument";
    case Error::Kind::cancelled: return "cancelled";
    }
    return "unknown";
}

void throw_error(Error::Kind kind, const std::string& file, const std::string& what) {
    throw Error(kind, file.empty() ? what : file + ": " + what);
}

}  // namespace lodforge
