// HugePageAllocator: the allocator of the hierarchy's node and triangle
// arrays. On Linux, blocks of 2 MiB or more are whole, 2 MiB-aligned pages
// marked for transparent huge pages; smaller ones, and all blocks elsewhere,
// keep their type's alignment and their size.
#include <gridfree/geometry/HugePageAllocator.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using gridfree::HugePageAllocator;
using gridfree::detail::HugePageRoundedBytes;
using gridfree::detail::kHugePageBytes;

struct alignas(64) CacheLine
{
  float Values[16];
};

std::uintptr_t Address(const void* p)
{
  return reinterpret_cast<std::uintptr_t>(p);
}

#if defined(__linux__)
// The kernel's transparent huge page mode: the bracketed word of
// /sys/kernel/mm/transparent_hugepage/enabled, or "" where there is none.
std::string TransparentHugePageMode()
{
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(in, line);
  const auto open = line.find('['), close = line.find(']');
  return open == std::string::npos || close == std::string::npos
    ? std::string()
    : line.substr(open + 1, close - open - 1);
}

// THPeligible of the mapping that holds p in /proc/self/smaps: 1 when the
// kernel may back it with huge pages, 0 when not, -1 if not found.
int ThpEligible(const void* p)
{
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(in, line))
  {
    unsigned long long lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-')
    {
      inside = Address(p) >= lo && Address(p) < hi;
      continue;
    }
    if (inside && line.rfind("THPeligible:", 0) == 0)
    {
      return std::stoi(line.substr(12));
    }
  }
  return -1;
}
#endif
} // namespace

TEST(HugePageAllocator, RoundsOnlyLargeBlocksToWholeHugePages)
{
  EXPECT_EQ(HugePageRoundedBytes(0), 0u);
  EXPECT_EQ(HugePageRoundedBytes(100), 100u);
  EXPECT_EQ(HugePageRoundedBytes(kHugePageBytes - 1), kHugePageBytes - 1);
  EXPECT_EQ(HugePageRoundedBytes(kHugePageBytes), kHugePageBytes);
  EXPECT_EQ(HugePageRoundedBytes(kHugePageBytes + 1), 2 * kHugePageBytes);
  EXPECT_EQ(HugePageRoundedBytes(5 * kHugePageBytes - 7), 5 * kHugePageBytes);
}

TEST(HugePageAllocator, SmallBlocksKeepTheTypesAlignment)
{
  for (std::size_t n : { 1u, 3u, 100u, 1000u })
  {
    std::vector<CacheLine, HugePageAllocator<CacheLine>> lines(n);
    EXPECT_EQ(Address(lines.data()) % alignof(CacheLine), 0u) << n;
    std::vector<char, HugePageAllocator<char>> bytes(n, 'x');
    EXPECT_EQ(bytes.back(), 'x');
  }
}

TEST(HugePageAllocator, LargeBlocksAreAlignedToHugePagesAndUsable)
{
  const std::size_t n = 3 * kHugePageBytes / sizeof(double) + 5; // not a whole page count
  std::vector<double, HugePageAllocator<double>> values(n);
#if defined(__linux__) // elsewhere large blocks are ordinary aligned memory
  ASSERT_EQ(Address(values.data()) % kHugePageBytes, 0u);
#endif
  for (std::size_t i = 0; i < n; ++i)
  {
    values[i] = static_cast<double>(i);
  }
  double sum = 0.0;
  for (const double v : values)
  {
    sum += v;
  }
  EXPECT_EQ(sum, 0.5 * double(n) * double(n - 1));

  // Copies and growth go through the same allocator.
  auto copy = values;
  copy.push_back(-1.0);
#if defined(__linux__)
  EXPECT_EQ(Address(copy.data()) % kHugePageBytes, 0u);
#endif
  EXPECT_EQ(copy[n - 1], double(n - 1));
}

#if defined(__linux__)
TEST(HugePageAllocator, LargeBlocksAreMarkedForTransparentHugePages)
{
  const std::string mode = TransparentHugePageMode();
  if (mode != "always" && mode != "madvise")
  {
    GTEST_SKIP() << "transparent huge pages are '" << mode << "' on this system";
  }
  std::vector<double, HugePageAllocator<double>> large(2 * kHugePageBytes / sizeof(double));
  const int eligible = ThpEligible(large.data());
  if (eligible < 0)
  {
    GTEST_SKIP() << "this kernel's smaps has no THPeligible field";
  }
  EXPECT_EQ(eligible, 1) << "madvise(MADV_HUGEPAGE) was not applied to a 4 MiB block";
}
#endif
