// Ray/primitive kernels: the watertight ray/triangle test (Woop, Benthin
// and Wald 2013) and the 2D ray/segment test, with exact edge signs
// (ExactPredicates.h), and the answer of a ray query. The hierarchy
// (Bvh.h) calls them on the primitives of the leaves a ray enters.
#ifndef GRIDFREE_GEOMETRY_RAY_KERNELS_H
#define GRIDFREE_GEOMETRY_RAY_KERNELS_H

#include <gridfree/geometry/ExactPredicates.h>
#include <gridfree/math/Vector.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace gridfree
{
namespace detail
{
/// Per-ray constants of the primitive tests.
///
/// 3D follows the watertight ray/triangle test of Woop, Benthin and Wald
/// (2013): vertices are translated to the ray origin and sheared so that the
/// ray becomes the +z axis of a permuted frame (z = the dominant direction
/// axis); the triangle is hit iff the origin of the projected xy plane lies
/// inside the projected triangle, decided by the signs of three 2D edge
/// functions. The sheared coordinates of a vertex depend only on the vertex
/// and the ray, so neighbouring triangles see the same numbers along a shared
/// edge; with the edge signs exact (ExactSignedDifferenceOfProducts, the
/// higher-precision fallback of the paper), a ray through an edge or vertex
/// of a closed mesh hits at least one of the triangles around it.
template <int DIM>
struct RayFrame;

template <>
struct RayFrame<3>
{
  Vec3 Origin;
  Vec3 Direction;
  int Kx, Ky, Kz;
  double Sx, Sy, Sz;

  RayFrame(const Vec3& origin, const Vec3& direction)
    : Origin(origin)
    , Direction(direction)
  {
    direction.cwiseAbs().maxCoeff(&this->Kz);
    this->Kx = (this->Kz + 1) % 3;
    this->Ky = (this->Kx + 1) % 3;
    if (direction[this->Kz] < 0.0)
    {
      std::swap(this->Kx, this->Ky); // keeps the winding of the projection
    }
    this->Sx = direction[this->Kx] / direction[this->Kz];
    this->Sy = direction[this->Ky] / direction[this->Kz];
    this->Sz = 1.0 / direction[this->Kz];
  }

  /// The projection of the test: the axes of the projected plane and the
  /// shear along the dominant axis (each of magnitude at most 1).
  void Projection(int (&axis)[2], double (&shear)[2]) const
  {
    axis[0] = this->Kx;
    axis[1] = this->Ky;
    shear[0] = this->Sx;
    shear[1] = this->Sy;
  }

  /// Hit of the triangle with t in [tMin, tMax]: t and the weights of v[0..2].
  /// Rays parallel to the triangle's plane (including rays in that plane)
  /// and zero-area triangles never hit.
  bool Intersect(const Vec3 (&v)[3], double tMin, double tMax, double& t, Vec3& w) const
  {
    double px[3], py[3], pz[3];
    for (int i = 0; i < 3; ++i)
    {
      const Vec3 p = v[i] - this->Origin;
      px[i] = p[this->Kx] - this->Sx * p[this->Kz];
      py[i] = p[this->Ky] - this->Sy * p[this->Kz];
      pz[i] = this->Sz * p[this->Kz];
    }
    // Edge functions; each one is the weight of the opposite vertex.
    const double u = ExactSignedDifferenceOfProducts(px[2], py[1], py[2], px[1]);
    const double s = ExactSignedDifferenceOfProducts(px[0], py[2], py[0], px[2]);
    const double r = ExactSignedDifferenceOfProducts(px[1], py[0], py[1], px[0]);
    if ((u < 0.0 || s < 0.0 || r < 0.0) && (u > 0.0 || s > 0.0 || r > 0.0))
    {
      return false;
    }
    // Same-signed terms: det is 0 only if all are (degenerate projection).
    const double det = u + s + r;
    if (det == 0.0)
    {
      return false;
    }
    const double tHit = (u * pz[0] + s * pz[1] + r * pz[2]) / det;
    if (!(tHit >= tMin && tHit <= tMax) || !std::isfinite(tHit))
    {
      return false;
    }
    // The projection of a triangle parallel to the ray has zero area only in
    // exact arithmetic; rounding of the shear can leave a sliver around the
    // ray. Reject those exactly (rare: only reached for an accepted hit).
    if (!CrossesPlane(v[0], v[1], v[2], this->Direction))
    {
      return false;
    }
    t = tHit;
    w = Vec3(u, s, r) / det;
    return true;
  }
};

/// 2D: the side of the ray line of each segment end is the exact sign of
/// cross(d, p - o) (for the rounded p - o, the same number for both segments
/// sharing a vertex), so a ray through a vertex of a closed polyline hits
/// at least one of its segments. t is interpolated, as in 3D, along the
/// dominant axis of the direction.
template <>
struct RayFrame<2>
{
  Vec2 Origin;
  Vec2 Direction;
  int Kz;
  double Sz;

  RayFrame(const Vec2& origin, const Vec2& direction)
    : Origin(origin)
    , Direction(direction)
  {
    this->Kz = std::abs(direction[1]) > std::abs(direction[0]) ? 1 : 0;
    this->Sz = 1.0 / direction[this->Kz];
  }

  /// The projection of the test: the side of the line of the segment ends,
  /// cross(d, p - o), is the sign of p[axis] - shear p[Kz] - o's, up to
  /// a sign fixed per ray (|shear| <= 1).
  void Projection(int (&axis)[1], double (&shear)[1]) const
  {
    axis[0] = 1 - this->Kz;
    shear[0] = this->Direction[1 - this->Kz] / this->Direction[this->Kz];
  }

  /// Hit of the segment with t in [tMin, tMax]: t and the weights of v[0..1].
  /// Segments along the ray line and zero-length segments never hit.
  bool Intersect(const Vec2 (&v)[2], double tMin, double tMax, double& t, Vec2& w) const
  {
    const Vec2 p = v[0] - this->Origin;
    const Vec2 q = v[1] - this->Origin;
    const Vec2& d = this->Direction;
    const double cp = ExactSignedDifferenceOfProducts(d[0], p[1], d[1], p[0]);
    const double cq = ExactSignedDifferenceOfProducts(d[0], q[1], d[1], q[0]);
    if ((cp > 0.0 && cq > 0.0) || (cp < 0.0 && cq < 0.0) || (cp == 0.0 && cq == 0.0))
    {
      return false;
    }
    const double den = cq - cp; // |cp| + |cq| > 0
    const double wp = cq / den;
    const double wq = -cp / den;
    const double tHit = (wp * p[this->Kz] + wq * q[this->Kz]) * this->Sz;
    if (!(tHit >= tMin && tHit <= tMax) || !std::isfinite(tHit))
    {
      return false;
    }
    t = tHit;
    w = Vec2(wp, wq);
    return true;
  }
};
} // namespace detail

/// Result of a ray query: the hit is origin + t * direction.
template <int DIM>
struct RayHit
{
  double t = std::numeric_limits<double>::infinity();
  std::int64_t primitive = -1; // ORIGINAL index, as passed to Bvh::Build
  Vec<DIM> barycentric = Vec<DIM>::Zero(); // weights of the primitive's vertices
  Vec<DIM> point = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
  bool Hit() const { return this->primitive >= 0; }
};
} // namespace gridfree

#endif
