// The one exception type of the core. Anything the user can cause (a bad file, a bad argument, a full
// disk) is reported as lodforge::Error with a message meant for a human; callers catch it at the edge
// (CLI main, studio job) and show what(). Internal invariants use assert instead.
#pragma once

#include <stdexcept>
#include <string>

namespace lodforge {

class Error : public std::runtime_error {
public:
    enum class Kind {
        io,          // cannot open, read, write, rename; disk full; permission
        format,      // the file is not what it claims (bad header, truncated, wrong types)
        invalid,     // the data parses but is unusable (NaN, index out of range, empty)
        unsupported, // a valid file using something we do not implement
        argument,    // a caller-supplied parameter is out of range
        cancelled,   // the user asked to stop
    };

    Error(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    Kind kind() const noexcept { return kind_; }

private:
    Kind kind_;
};

// The kind's name in lower case ("io", "format", ...), as the Python module's Error.kind and tests show it.
const char* kind_name(Error::Kind kind) noexcept;

// Message helpers so every error names its file the same way: "<file>: <what>".
[[noreturn]] void throw_error(Error::Kind kind, const std::string& file, const std::string& what);

}  // namespace lodforge
