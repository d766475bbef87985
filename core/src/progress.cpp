#include "lodforge/progress.h"

#include "lodforge/error.h"

#include <string>

namespace lodforge {

void check_progress(Progress* progress, double fraction, std::string_view stage) {
    if (!progress) return;
    progress->report(fraction, stage);
    if (progress->cancelled()) throw Error(Error::Kind::cancelled, "cancelled during " + std::string(stage));
}

}  // namespace lodforge
