// What an application filter's output says of the caches its solves used
// (the Estimator property): the application filters build their output
// from internal solves, whose own outputs carry the cache's arrays and
// field data (GridFreePointEstimates.cxx, AddCacheFields).
#ifndef GridFreeCacheSummary_h
#define GridFreeCacheSummary_h

#include <vector>

class vtkDataSet;

namespace gridfree
{
// Copies to `output` the point array FromBoundaryCache and the field data
// PointsFromCache, PointsWalkedInShell and OutsidePoints of the first solve
// (solves at the same points with caches of the same lattice and shell
// answer the same points), and CacheSpheres, CacheWalks, CacheWalksRun
// (0: every cache was reused as it was) and CacheSeconds summed over
// `solves` (each with its own cache).
void AddCacheSummary(const std::vector<vtkDataSet*>& solves, vtkDataSet* output);
} // namespace gridfree

#endif
