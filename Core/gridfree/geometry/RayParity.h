// Inside or outside a closed surface (closed polylines in 2D) by ray parity:
// a point is enclosed when a ray from it crosses the surface an odd number
// of times. Orientation plays no part. Several well-spread rays vote, so a
// single ray that slips through a crack or grazes an edge does not decide
// (MeshSignedDistance.h explains the choices). A surface may be split over
// several hierarchies (the parts of a mixed boundary): crossings add up.
#ifndef gridfree_geometry_RayParity_h
#define gridfree_geometry_RayParity_h

#include <gridfree/geometry/Bvh.h>
#include <gridfree/math/Vector.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

namespace gridfree
{
// Rays that vote on a point's side.
constexpr int kParityRays = 5;

// Well-spread unit directions with irrational components. 2D: five
// directions 72° apart, turned by an irrational fraction of the circle.
// 3D: the five-point Fibonacci lattice of the sphere (every pair at least
// 87° apart), rotated about an irrational axis by one radian, so that no
// direction lies in a coordinate plane or along a lattice diagonal.
template <int DIM>
std::array<Vec<DIM>, kParityRays> ParityRayDirections()
{
  std::array<Vec<DIM>, kParityRays> d;
  if constexpr (DIM == 2)
  {
    const double turn = 0.5 * (std::sqrt(5.0) - 1.0); // golden ratio − 1
    for (int k = 0; k < kParityRays; ++k)
    {
      // Order 0, 2, 4, 1, 3: the first three (the usual vote) are not
      // neighbours, at least 72° apart and spanning the whole circle.
      const int slot = (2 * k) % kParityRays;
      const double angle = 2.0 * M_PI * (slot + turn) / kParityRays;
      d[k] = Vec<DIM>(std::cos(angle), std::sin(angle));
    }
  }
  else
  {
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    const Eigen::AngleAxisd rotation(1.0, Vec3(1.0, std::sqrt(2.0), std::sqrt(3.0)).normalized());
    for (int k = 0; k < kParityRays; ++k)
    {
      const double z = 1.0 - (2.0 * k + 1.0) / kParityRays;
      const double r = std::sqrt(1.0 - z * z);
      const double phi = golden * k;
      d[k] = (rotation * Vec3(r * std::cos(phi), r * std::sin(phi), z)).normalized();
    }
  }
  return d;
}

// Crossings of the ray x + t d (t >= 0) with the primitives of `tree`, hits
// closer together than `gap` counted once (a ray through a shared edge or
// vertex that several primitives report). Each query starts just beyond
// the previous hit; `limit` (more than the primitives) guards against a
// pathological input. With `counts`, only the primitives it accepts count
// (a mixed boundary's insulating sheets close nothing).
template <int DIM>
std::int64_t CountRayCrossings(const Bvh<DIM>& tree, const Vec<DIM>& x, const Vec<DIM>& direction,
  double gap, std::int64_t limit,
  const std::function<bool(std::int64_t)>& counts = std::function<bool(std::int64_t)>())
{
  std::int64_t count = 0;
  double tMin = 0.0;
  const double inf = std::numeric_limits<double>::infinity();
  for (std::int64_t hits = 0; hits < limit; ++hits)
  {
    const RayHit<DIM> hit = tree.Intersect(x, direction, inf, tMin);
    if (!hit.Hit())
    {
      break;
    }
    count += !counts || counts(hit.primitive) ? 1 : 0;
    const double next = hit.t + gap;
    tMin = next > hit.t ? next : std::nextafter(hit.t, inf);
  }
  return count;
}

// The majority of the parity votes of the rays along `directions`;
// crossings(direction) counts a ray's crossings. Stops as soon as a
// majority agrees.
template <int DIM, class Crossings>
bool MajorityParityVote(const std::array<Vec<DIM>, kParityRays>& directions, const Crossings& crossings)
{
  int inside = 0;
  int outside = 0;
  for (int k = 0; k < kParityRays; ++k)
  {
    if (crossings(directions[k]) % 2 == 1)
    {
      ++inside;
    }
    else
    {
      ++outside;
    }
    if (2 * inside > kParityRays)
    {
      return true;
    }
    if (2 * outside > kParityRays)
    {
      return false;
    }
  }
  return inside > outside;
}
// Whether x is enclosed by a closed mesh boundary (the majority of
// kParityRays ray parities); false outside its box.
template <int DIM, class MeshBoundary>
bool InsideClosedMesh(const MeshBoundary& boundary, const Vec<DIM>& x)
{
  for (int i = 0; i < DIM; ++i)
  {
    if (!(x[i] >= boundary.BoundsMin()[i] && x[i] <= boundary.BoundsMax()[i]))
    {
      return false;
    }
  }
  static const std::array<Vec<DIM>, kParityRays> directions = ParityRayDirections<DIM>();
  const double gap = 1e-9 * boundary.Diagonal();
  const auto limit = static_cast<std::int64_t>(boundary.NumberOfPrimitives()) + 1;
  return MajorityParityVote<DIM>(directions, [&](const Vec<DIM>& d) {
    return CountRayCrossings<DIM>(boundary.Hierarchy(), x, d, gap, limit);
  });
}
} // namespace gridfree

#endif
