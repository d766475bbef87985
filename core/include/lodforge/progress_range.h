// One stage of a longer operation as a Progress of its own: the stage reports 0..1 and the caller's
// progress sees [begin, end) of its range; cancellation passes through. Used where one job chains several
// algorithms (LOD chains: a simplification and a measurement per level).
#pragma once

#include "lodforge/progress.h"

#include <algorithm>

namespace lodforge {

class ProgressRange final : public Progress {
public:
    ProgressRange(Progress* parent, double begin, double end) : parent_(parent), begin_(begin), end_(end) {}
    void report(double fraction, std::string_view stage) override {
        if (parent_) parent_->report(begin_ + (end_ - begin_) * std::clamp(fraction, 0.0, 1.0), stage);
    }
    bool cancelled() const override { return parent_ && parent_->cancelled(); }

private:
    Progress* parent_;
    double begin_, end_;
};

}  // namespace lodforge
