// An allocator for large working arrays that asks Linux for transparent huge pages.
//
// Code that reads big arrays in an order unrelated to memory (the simplifier's cost-ordered walk) misses
// the TLB on nearly every record with 4 KiB pages; with 2 MiB pages the whole working set fits the TLB.
// Where transparent huge pages are `madvise` (the common default) a region only gets them when asked,
// so blocks of at least 2 MiB are 2 MiB-aligned and marked MADV_HUGEPAGE. Elsewhere, and for small
// blocks, this is the ordinary allocator; the advice is only a hint (no error if the kernel declines).
// lodstrips_runtime.h has its own copy on purpose: that header is shipped alone to engines.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace lodforge {

template <class T>
struct HugePageAllocator {
    using value_type = T;
    static constexpr std::size_t kHuge = std::size_t(2) << 20;

    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) {}

    static bool huge(std::size_t n) { return n * sizeof(T) >= kHuge; }
    static std::size_t rounded(std::size_t n) { return (n * sizeof(T) + kHuge - 1) / kHuge * kHuge; }

    // Small blocks: one cache line's alignment, so 64-byte records never straddle two lines.
    static constexpr std::align_val_t kSmall{alignof(T) < 64 ? 64 : alignof(T)};

    T* allocate(std::size_t n) {
        if (!huge(n)) return static_cast<T*>(::operator new(n * sizeof(T), kSmall));
        void* p = ::operator new(rounded(n), std::align_val_t(kHuge));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        madvise(p, rounded(n), MADV_HUGEPAGE);
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) {
        if (!huge(n)) ::operator delete(p, kSmall);
        else ::operator delete(p, std::align_val_t(kHuge));
    }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const { return true; }
};

template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace lodforge
