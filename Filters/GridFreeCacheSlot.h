// Where a built problem keeps its solution caches between executions: the
// boundary value cache (gridfree/cache/BoundaryValueCache.h) and the sphere
// cache (gridfree/cache/SphereCache.h). The problem builder hands the same
// slot to every problem built from the same boundary, boundary values,
// source, equation, walks' settings and seed, and empties the part of a
// cache whose own settings changed. A cache is built on first use, by the
// batch that needs it (GridFreeCacheAnswers.h), with progress and abort; a
// probe that moves reuses it.
// Private to the GridFree::Filters module.
#ifndef GridFreeCacheSlot_h
#define GridFreeCacheSlot_h

#include <gridfree/cache/BoundaryValueCache.h>
#include <gridfree/cache/SphereCache.h>

#include <memory>

namespace gridfree
{
struct CacheSlot
{
  std::shared_ptr<BoundaryValueCache<2>> Boundary2;
  std::shared_ptr<BoundaryValueCache<3>> Boundary3;
  std::shared_ptr<SphereCache<2>> Spheres2;
  std::shared_ptr<SphereCache<3>> Spheres3;

  template <int DIM>
  std::shared_ptr<BoundaryValueCache<DIM>>& BoundaryCache()
  {
    if constexpr (DIM == 2)
    {
      return this->Boundary2;
    }
    else
    {
      return this->Boundary3;
    }
  }

  template <int DIM>
  std::shared_ptr<SphereCache<DIM>>& Spheres()
  {
    if constexpr (DIM == 2)
    {
      return this->Spheres2;
    }
    else
    {
      return this->Spheres3;
    }
  }
};
} // namespace gridfree

#endif
