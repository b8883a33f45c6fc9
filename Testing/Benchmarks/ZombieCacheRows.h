// The authors' boundary value caching (zombie's bvc::BoundaryValueCachingSolver,
// Miller, Sawhney, Crane and Gkioulekas 2023) on the cache benchmark's
// Dirichlet problem, beside the project's sphere cache: built only when
// their public sources are given at configure time
// (GRIDFREE_ZOMBIE_SOURCE_DIR, Testing/Benchmarks/CMakeLists.txt). Plain
// types only, as in ZombieStarsRows.h (their pcg32 and the core's share a
// name).
#ifndef GRIDFREE_BENCHMARKS_ZOMBIECACHEROWS_H
#define GRIDFREE_BENCHMARKS_ZOMBIECACHEROWS_H

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace gridfree
{
namespace bench
{
struct ZombieCacheSettings
{
  int CachePoints = 1024;   // absorbing-boundary cache points
  int GradientWalks = 640;  // walks for ∂u/∂n at each cache point (their default)
  double Epsilon = 1e-3;    // both ε-shells; the cache points sit 5ε inside (their default)
};

struct ZombieCacheResult
{
  double SetupSeconds = 0.0; // fcpw's hierarchy
  double Seconds = 0.0;      // samples, walks, splatting, the near-boundary walks
  double Rmse = 0.0;
  int NearBoundaryPoints = 0; // answered by their own walks, not the cache
};

// Laplace with u = exact on the whole (closed) mesh, evaluated at `points`
// (all inside) by zombie's boundary value caching in float, on every core.
ZombieCacheResult RunZombieBoundaryValueCaching(const std::vector<std::array<double, 3>>& vertices,
  const std::vector<std::array<std::int64_t, 3>>& triangles,
  const std::function<double(const std::array<double, 3>&)>& exact,
  const std::vector<std::array<double, 3>>& points, const ZombieCacheSettings& settings);
} // namespace bench
} // namespace gridfree

#endif
