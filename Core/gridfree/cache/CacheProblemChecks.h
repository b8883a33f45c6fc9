// What the caches (BoundaryValueCache.h, SphereCache.h) ask of a problem:
// volume sources only (and Dirichlet conditions only, for the boundary
// value cache), and which side of the
// closed mesh is its inside (the orientation that makes the primitives'
// normals point outward, from the sign of the volume, 3D, or area, 2D,
// they enclose): they answer interior problems.
#ifndef GRIDFREE_CACHE_CACHE_PROBLEM_CHECKS_H
#define GRIDFREE_CACHE_CACHE_PROBLEM_CHECKS_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/problem/Problem.h>

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace gridfree
{
// The signed volume (3D) or area (2D) a mesh encloses: positive for
// right-handed triangles facing outward (3D) and for counter-clockwise
// loops (2D).
template <int DIM>
double EnclosedSignedMeasure(const Boundary<DIM>& boundary)
{
  const std::vector<Vec<DIM>>& v = boundary.MeshVertices();
  double measure = 0.0;
  for (const auto& ids : boundary.MeshPrimitives())
  {
    if constexpr (DIM == 3)
    {
      const Vec<3>& a = v[static_cast<std::size_t>(ids[0])];
      const Vec<3>& b = v[static_cast<std::size_t>(ids[1])];
      const Vec<3>& c = v[static_cast<std::size_t>(ids[2])];
      measure += a.dot(b.cross(c)) / 6.0;
    }
    else
    {
      const Vec<2>& a = v[static_cast<std::size_t>(ids[0])];
      const Vec<2>& b = v[static_cast<std::size_t>(ids[1])];
      measure += 0.5 * (a[0] * b[1] - b[0] * a[1]);
    }
  }
  return measure;
}

// +1 when the primitives' own normals (SimplexUnitNormal) face outward,
// −1 when they face inward: 3D right-handed triangles of a positive volume
// face outward; 2D, the left normal of a counter-clockwise loop faces
// inward. Throws std::invalid_argument for a mesh enclosing nothing.
template <int DIM>
int OutwardOrientation(const Boundary<DIM>& boundary)
{
  if (!boundary.IsMesh() || boundary.MeshPrimitives().empty())
  {
    throw std::invalid_argument("the cache needs a mesh boundary");
  }
  const double measure = EnclosedSignedMeasure<DIM>(boundary);
  if (!(std::abs(measure) > 0.0))
  {
    throw std::invalid_argument("the cache needs a closed mesh enclosing a volume");
  }
  return (DIM == 3) == (measure > 0.0) ? 1 : -1;
}

// Throws std::invalid_argument for point or curve sources; `name` names the
// cache in the message.
template <int DIM>
void RequireVolumeSourcesOnly(const Problem<DIM>& problem, const char* name)
{
  const SourceSet<DIM>* sources = problem.GetSources();
  if (sources && (sources->Points || sources->Curves))
  {
    throw std::invalid_argument(
      std::string(name) + " takes volume sources only (yet): no point or curve sources");
  }
}

// Throws std::invalid_argument unless the problem has Dirichlet
// conditions only and no point or curve sources.
template <int DIM>
void RequireDirichletWithVolumeSources(const Problem<DIM>& problem, const char* name)
{
  if (problem.GetMixedBoundary())
  {
    throw std::invalid_argument(std::string(name) +
      " answers Dirichlet conditions only (yet): no Neumann or Robin parts");
  }
  RequireVolumeSourcesOnly<DIM>(problem, name);
}

// Whether x lies outside the closed mesh (`orientation` from
// OutwardOrientation; `hit` its closest point).
template <int DIM>
bool OutsideClosedMesh(const Boundary<DIM>& boundary, int orientation, const Vec<DIM>& x,
  const ClosestPointResult<DIM>& hit)
{
  return boundary.Side(x, hit) * orientation > 0;
}
} // namespace gridfree

#endif
