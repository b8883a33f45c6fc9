// The geometric side of a Dirichlet boundary that is not a BVH over a mesh:
// implicit surfaces, CSG trees, Bézier curves. Boundary<DIM> keeps its mesh
// path free of virtual calls and uses this interface for everything else.
//
// Walk on spheres needs exactly two queries (paper Sec. 5.1):
// * Distance(x): the radius of an empty ball around x. It may be a LOWER
//   bound of the true distance (a smaller ball is still inside the domain, so
//   the estimator stays unbiased) but must never exceed it, and it must be
//   close to the truth near the boundary, where the walk decides to stop.
// * ClosestPoint(x): where the walk takes its boundary value once it is
//   within ε of the boundary.
#ifndef GRIDFREE_GEOMETRY_BOUNDARY_GEOMETRY_H
#define GRIDFREE_GEOMETRY_BOUNDARY_GEOMETRY_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/ClosestPointResult.h>
#include <gridfree/math/Vector.h>

namespace gridfree
{
template <int DIM>
class BoundaryGeometry
{
public:
  virtual ~BoundaryGeometry() = default;

  // Conservative distance to the boundary (never more than the truth).
  virtual double Distance(const Vec<DIM>& x) const = 0;

  // A walk step's radius: at most Distance(x) and at least
  // Distance(x) / (1 + relaxation), equal to it whenever it is below
  // epsilon (so that walks stop where they would with Distance). Geometries
  // whose distance searches a hierarchy (CSG of meshes) answer from cached
  // bounds; the default is Distance(x).
  virtual double StepRadius(const Vec<DIM>& x, double /*relaxation*/, double /*epsilon*/) const
  {
    return this->Distance(x);
  }

  // A boundary point near x, with `distance` = |x − point| and the part or
  // primitive it lies on (see ClosestPointResult).
  virtual ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const = 0;

  // Unit normal of the boundary at a point returned by ClosestPoint (zero
  // where there is none); only used to pick a side for points on the boundary.
  virtual Vec<DIM> Normal(const ClosestPointResult<DIM>& hit) const = 0;

  // A box that holds the whole boundary; empty when it is unbounded.
  virtual BoundingBox<DIM> Bounds() const = 0;

  // Number of parts (CSG leaves, curves, primitives) a ClosestPointResult's
  // `primitive` can name.
  virtual std::int64_t NumberOfParts() const = 0;

  // Whether x lies inside the boundary, where the geometry can tell (false
  // where it cannot). Only Problem::LeadingGuide asks, to choose the points
  // it measures the screened guide's agreement at: a wrong answer costs
  // variance, never bias.
  virtual bool Encloses(const Vec<DIM>& /*x*/) const { return false; }
};
} // namespace gridfree

#endif
