// The answer of a closest-point query, shared by every boundary
// representation (meshes, implicit surfaces, Bézier curves).
#ifndef GRIDFREE_GEOMETRY_CLOSEST_POINT_RESULT_H
#define GRIDFREE_GEOMETRY_CLOSEST_POINT_RESULT_H

#include <gridfree/math/Vector.h>

#include <cstdint>
#include <limits>

namespace gridfree
{
template <int DIM>
struct ClosestPointResult
{
  // The closest boundary point found and its distance from the query.
  Vec<DIM> point = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
  double distance = std::numeric_limits<double>::infinity();
  // Meshes: the original index of the closest primitive and the barycentric
  // weights of its vertices. Implicit boundaries: the part of a CSG tree the
  // point lies on (0 for a single function). Bézier curves: the curve, with
  // weights (1 − t, t) of its two end points.
  std::int64_t primitive = -1;
  Vec<DIM> barycentric = Vec<DIM>::Zero();
};
} // namespace gridfree

#endif
