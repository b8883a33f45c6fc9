// The counting global operator new behind AllocationCounter.h.
#include "AllocationCounter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace
{
std::atomic<int> Counting{ 0 };
std::atomic<long> Allocations{ 0 };

void* CountedAllocation(std::size_t size)
{
  if (Counting.load(std::memory_order_relaxed) > 0)
  {
    Allocations.fetch_add(1, std::memory_order_relaxed);
  }
  if (void* p = std::malloc(size ? size : 1))
  {
    return p;
  }
  throw std::bad_alloc();
}
} // namespace

void* operator new(std::size_t size)
{
  return CountedAllocation(size);
}
void* operator new[](std::size_t size)
{
  return CountedAllocation(size);
}
void operator delete(void* p) noexcept
{
  std::free(p);
}
void operator delete[](void* p) noexcept
{
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept
{
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept
{
  std::free(p);
}

namespace gridfree
{
namespace testing
{
AllocationCounter::AllocationCounter()
{
  Allocations = 0;
  Counting.fetch_add(1);
}

AllocationCounter::~AllocationCounter()
{
  this->Stop();
}

long AllocationCounter::Stop()
{
  if (this->Running)
  {
    this->Running = false;
    Counting.fetch_sub(1);
  }
  return Allocations.load();
}
} // namespace testing
} // namespace gridfree
