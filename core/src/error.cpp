#include "lodforge/error.h"

namespace lodforge {

void throw_error(Error::Kind kind, const std::string& file, const std::string& what) {
    throw Error(kind, file.empty() ? what : file + ": " + what);
}

}  // namespace lodforge
