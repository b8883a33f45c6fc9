// Allocator for the large arrays of a search hierarchy: blocks of 2 MiB or
// more are aligned to 2 MiB and marked for transparent huge pages on Linux.
//
// Why: a random closest-point query over a hierarchy larger than the caches
// touches a few dozen cache lines on as many different 4 KiB pages, and each
// page it has not seen lately costs a page walk. One 2 MiB page covers 512 of
// them. Measured near the surface of 327k- and 1.3M-triangle spheres: 3-15%
// faster in alternating runs (Documentation/Performance.md, "Huge pages").
//
// The mark is a hint: where the kernel's transparent huge pages are off (or
// set to "never"), or on other systems, memory is plain and nothing else
// changes. Smaller blocks come from the ordinary aligned allocation, so small
// hierarchies cost no more memory than before.
#ifndef GRIDFREE_GEOMETRY_HUGE_PAGE_ALLOCATOR_H
#define GRIDFREE_GEOMETRY_HUGE_PAGE_ALLOCATOR_H

#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace gridfree
{
namespace detail
{
constexpr std::size_t kHugePageBytes = std::size_t(1) << 21;

/// Bytes actually reserved for a request of `bytes`: whole huge pages from
/// kHugePageBytes on (so the last page can be huge too), unchanged below.
inline std::size_t HugePageRoundedBytes(std::size_t bytes)
{
  return bytes >= kHugePageBytes ? (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1) : bytes;
}

/// Aligned block of `bytes` (alignment at least `alignment`, a power of two);
/// throws std::bad_alloc. Release with FreeHugePageBlock.
inline void* AllocateHugePageBlock(std::size_t bytes, std::size_t alignment)
{
#if defined(__linux__)
  const bool huge = bytes >= kHugePageBytes;
  const std::size_t rounded = HugePageRoundedBytes(bytes);
  std::size_t align = huge ? kHugePageBytes : alignment;
  if (align < sizeof(void*))
  {
    align = sizeof(void*); // posix_memalign's minimum
  }
  void* p = nullptr;
  if (posix_memalign(&p, align, rounded == 0 ? align : rounded) != 0 || p == nullptr)
  {
    throw std::bad_alloc();
  }
#if defined(MADV_HUGEPAGE)
  if (huge)
  {
    // Advice only: failure (e.g. THP compiled out) leaves ordinary pages.
    (void)madvise(p, rounded, MADV_HUGEPAGE);
  }
#endif
  return p;
#else
  // Elsewhere: the ordinary aligned allocation (no huge-page advice).
  return ::operator new(bytes, std::align_val_t(alignment));
#endif
}

inline void FreeHugePageBlock(void* p, std::size_t alignment) noexcept
{
#if defined(__linux__)
  (void)alignment;
  std::free(p);
#else
  ::operator delete(p, std::align_val_t(alignment));
#endif
}
} // namespace detail

/// std::allocator replacement for large, long-lived arrays (see above).
template <typename T>
struct HugePageAllocator
{
  using value_type = T;

  HugePageAllocator() noexcept = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept
  {
  }

  T* allocate(std::size_t n)
  {
    if (n > std::numeric_limits<std::size_t>::max() / sizeof(T))
    {
      throw std::bad_alloc();
    }
    return static_cast<T*>(detail::AllocateHugePageBlock(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept { detail::FreeHugePageBlock(p, alignof(T)); }

  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const noexcept
  {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept
  {
    return false;
  }
};
} // namespace gridfree

#endif
