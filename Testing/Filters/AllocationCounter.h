// Counts heap allocations, to show that walks never allocate.
//
// AllocationCounter.cxx replaces the global operator new of the program it is
// linked into with one that counts while an AllocationCounter is running, so
// these tests are a program of their own (GridFreeAllocationTests), not part
// of the other suites (nor of the sanitizer build, whose allocator is ASan's).
// The core uses no Eigen dynamic-size types (whose memory bypasses operator
// new) and calls the C allocator only for the BVH's node and triangle arrays
// (posix_memalign, HugePageAllocator.h), which are filled when a boundary is
// set, before any walk; every allocation a walk could make is seen.
#ifndef GRIDFREE_TESTING_ALLOCATIONCOUNTER_H
#define GRIDFREE_TESTING_ALLOCATIONCOUNTER_H

#include "EstimatorChecks.h"
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/math/Vector.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <gtest/gtest.h>

#include <vector>

namespace gridfree
{
namespace testing
{
// Counts the allocations (operator new, any thread) between its construction
// and Stop().
class AllocationCounter
{
public:
  AllocationCounter();
  ~AllocationCounter();
  long Stop();

private:
  bool Running = true;
};

constexpr int WarmUpPoints = 4;
constexpr int CountedPoints = 8;
constexpr int WalksPerPoint = 64;

// Start points in the ball of radius 0.6 about the origin, or (outside) in
// the shell between radii 1.3 and 2.
template <int DIM>
std::vector<Vec<DIM>> StartPoints(int count, std::uint32_t seed, bool outside = false)
{
  return outside ? RandomPointsInBall<DIM>(count, 2.0, seed, 1.3)
                 : RandomPointsInBall<DIM>(count, 0.6, seed);
}

// Allocations made by `estimator`'s EstimatePoint over CountedPoints points,
// after WarmUpPoints other points (buffers that grow to their working size,
// e.g. the curve sources' scratch or a per-thread source, may allocate then).
template <int DIM, class Estimator>
long AllocationsOfWalks(Estimator& estimator, int components, bool outside = false)
{
  RunningStatistics stats(components);
  WalkCounters counters;
  auto run = [&](const std::vector<Vec<DIM>>& points) {
    for (const Vec<DIM>& p : points)
    {
      const double xyz[3] = { p[0], p[1], DIM == 3 ? p[DIM - 1] : 0.0 };
      stats.Reset();
      estimator.EstimatePoint(xyz, 7, 0, WalksPerPoint, stats, counters);
    }
  };
  const auto warm = StartPoints<DIM>(WarmUpPoints, 1, outside);
  const auto counted = StartPoints<DIM>(CountedPoints, 2, outside);
  run(warm);
  AllocationCounter counter;
  run(counted);
  const long allocations = counter.Stop();
  EXPECT_GT(counters.Steps, counters.Walks) << "the walks did not walk";
  return allocations;
}
} // namespace testing
} // namespace gridfree

#endif
