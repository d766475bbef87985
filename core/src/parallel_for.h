// Internal: a loop over [0, n) cut into one contiguous range per thread, for per-index work whose
// result does not depend on how the range is cut (so outputs are identical at any thread count).
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace lodforge::detail {

// f(begin, end) on `threads` ranges, the first on this thread; below `min_n` items, or with one thread,
// a single call here. An exception from any range is rethrown here after every thread has ended (a
// thread that threw would otherwise end the process).
template <class F>
void parallel_for(std::size_t n, unsigned threads, std::size_t min_n, F&& f) {
    if (n < min_n || threads <= 1) {
        f(std::size_t(0), n);
        return;
    }
    const std::size_t chunk = (n + threads - 1) / threads;
    std::vector<std::exception_ptr> errors(threads);
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) {
        const std::size_t b = std::min(n, t * chunk), e = std::min(n, b + chunk);
        if (b >= e) break;
        pool.emplace_back([&f, &errors, t, b, e] {
            try {
                f(b, e);
            } catch (...) {
                errors[t] = std::current_exception();
            }
        });
    }
    try {
        f(std::size_t(0), std::min(n, chunk));
    } catch (...) {
        errors[0] = std::current_exception();
    }
    for (auto& th : pool) th.join();
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
}

// `beside()` on a second thread while `here()` runs on this one (both here, in that order, with one
// thread). Like parallel_for, an exception from either is rethrown here once both have ended; when both
// throw, `here`'s wins.
template <class Here, class Beside>
void run_beside(unsigned threads, Here&& here, Beside&& beside) {
    if (threads <= 1) {
        here();
        beside();
        return;
    }
    std::exception_ptr beside_error, here_error;
    std::thread helper([&beside, &beside_error] {
        try {
            beside();
        } catch (...) {
            beside_error = std::current_exception();
        }
    });
    try {
        here();
    } catch (...) {
        here_error = std::current_exception();
    }
    helper.join();
    if (here_error) std::rethrow_exception(here_error);
    if (beside_error) std::rethrow_exception(beside_error);
}

}  // namespace lodforge::detail
