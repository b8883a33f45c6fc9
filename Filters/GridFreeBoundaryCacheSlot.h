// Where a built problem keeps its boundary value cache
// (gridfree/cache/BoundaryValueCache.h) between executions: the problem
// builder hands the same slot to every problem built from the same
// boundary, boundary values, source, equation, walks' settings, seed and
// cache settings, and a new, empty one when any of them changes. The cache
// itself is built on first use, by the batch that needs it
// (GridFreePointEstimates), with progress and abort; a probe that moves
// reuses it with no new walks.
// Private to the GridFree::Filters module.
#ifndef GridFreeBoundaryCacheSlot_h
#define GridFreeBoundaryCacheSlot_h

#include <gridfree/cache/BoundaryValueCache.h>

#include <memory>

namespace gridfree
{
struct BoundaryCacheSlot
{
  std::shared_ptr<BoundaryValueCache<2>> Cache2;
  std::shared_ptr<BoundaryValueCache<3>> Cache3;

  template <int DIM>
  std::shared_ptr<BoundaryValueCache<DIM>>& Get()
  {
    if constexpr (DIM == 2)
    {
      return this->Cache2;
    }
    else
    {
      return this->Cache3;
    }
  }
};
} // namespace gridfree

#endif
