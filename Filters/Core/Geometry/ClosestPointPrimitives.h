// Closest points on boundary primitives: segments (2D or 3D) and triangles (3D).
//
// These are the innermost kernels of every distance query, used both by the
// BVH leaves and on their own (e.g. as a brute-force reference). They must
// never produce NaN for finite input, including degenerate primitives coming
// from real meshes: zero-length segments, zero-area triangles (collinear or
// repeated vertices). A degenerate primitive is treated as the point set it
// really is, so the result is still its true closest point.
//
// Every function returns the point together with barycentric weights of the
// primitive's vertices (>= 0, summing to 1) that reproduce the point up to
// rounding, so callers can interpolate vertex data (e.g. boundary values).
#ifndef GRIDFREE_CORE_GEOMETRY_CLOSESTPOINTPRIMITIVES_H
#define GRIDFREE_CORE_GEOMETRY_CLOSESTPOINTPRIMITIVES_H

#include "Vector.h"

#include <Eigen/Geometry> // cross product

#include <limits>

namespace gridfree
{
/// Closest point on a primitive with NV vertices in DIM dimensions.
template <int DIM, int NV>
struct PrimitiveClosestPoint
{
  Vec<DIM> point;
  Eigen::Matrix<double, NV, 1> weights; // barycentric weights of the vertices
  double squaredDistance;               // |x - point|^2
};

namespace detail
{
/// Parameter t in [0, 1] of the closest point a + t (b - a) on segment [a, b].
/// A zero-length segment yields t = 0, i.e. its only point a.
template <int DIM>
inline double SegmentParameter(const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& ab)
{
  const double len2 = ab.squaredNorm();
  // `!(len2 > 0)` also rejects a NaN length; the division below is then safe.
  if (!(len2 > 0.0))
  {
    return 0.0;
  }
  const double t = ab.dot(x - a) / len2;
  return t <= 0.0 ? 0.0 : (t >= 1.0 ? 1.0 : t);
}

/// Point at parameter t; the end points are returned exactly (not a + 1 * ab),
/// so that vertex queries are bit-exact.
template <int DIM>
inline Vec<DIM> SegmentPoint(
  double t, const Vec<DIM>& a, const Vec<DIM>& b, const Vec<DIM>& ab)
{
  if (t <= 0.0)
  {
    return a;
  }
  if (t >= 1.0)
  {
    return b;
  }
  return a + t * ab;
}

/// A triangle is treated as degenerate (as the union of its edges) when
/// sin^2 of its angle at vertex a is below this. Around sqrt(eps) the error of
/// the projection onto a sliver's plane (~eps / sin) becomes larger than the
/// sliver's width (~sin), so the edge-based answer is then the more accurate.
constexpr double kDegenerateTriangleSin2 = 1e-15;
} // namespace detail

/// Closest point on the segment [a, b] (any dimension).
template <int DIM>
inline PrimitiveClosestPoint<DIM, 2> ClosestPointOnSegment(
  const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& b)
{
  const Vec<DIM> ab = b - a;
  const double t = detail::SegmentParameter<DIM>(x, a, ab);
  PrimitiveClosestPoint<DIM, 2> r;
  r.point = detail::SegmentPoint<DIM>(t, a, b, ab);
  r.weights << 1.0 - t, t;
  r.squaredDistance = (x - r.point).squaredNorm();
  return r;
}

/// Squared distance to the segment [a, b]; same value as
/// ClosestPointOnSegment(x, a, b).squaredDistance, without the weights.
template <int DIM>
inline double SquaredDistanceToSegment(const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& b)
{
  const Vec<DIM> ab = b - a;
  const double t = detail::SegmentParameter<DIM>(x, a, ab);
  return (x - detail::SegmentPoint<DIM>(t, a, b, ab)).squaredNorm();
}

/// Closest point on triangle (a, b, c) in 3D.
///
/// The query is projected onto the triangle's plane and its barycentric
/// coordinates are computed with the dual basis of the edges (ac x n, n x ab),
/// which stays accurate for thin triangles, unlike formulations based on 2x2
/// determinants of dot products. If the projection is inside, it is the
/// answer. Otherwise the closest point lies on an edge whose opposite weight is
/// negative (at most two of them), which the robust segment kernel handles.
/// Degenerate triangles (collinear or repeated vertices) are the union of
/// their three edges.
inline PrimitiveClosestPoint<3, 3> ClosestPointOnTriangle(
  const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c)
{
  PrimitiveClosestPoint<3, 3> r;
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 n = ab.cross(ac);
  const double nn = n.squaredNorm();
  // Edge candidates; each flag is set for edges that may hold the answer.
  bool testBC = true, testCA = true, testAB = true;
  if (nn > detail::kDegenerateTriangleSin2 * ab.squaredNorm() * ac.squaredNorm())
  {
    const Vec3 ap = x - a;
    const double inv = 1.0 / nn;
    const double v = ap.dot(ac.cross(n)) * inv;
    const double w = ap.dot(n.cross(ab)) * inv;
    const double u = 1.0 - v - w;
    if (u >= 0.0 && v >= 0.0 && w >= 0.0)
    {
      r.point = a + v * ab + w * ac;
      r.weights << u, v, w;
      r.squaredDistance = (x - r.point).squaredNorm();
      return r;
    }
    testBC = u < 0.0;
    testCA = v < 0.0;
    testAB = w < 0.0;
    if (!(testBC || testCA || testAB))
    {
      testBC = testCA = testAB = true; // NaN query: keep the output defined
    }
  }

  // Outside (or degenerate): best of the candidate edges. Ties keep the first.
  r.squaredDistance = std::numeric_limits<double>::infinity();
  if (testAB)
  {
    const auto e = ClosestPointOnSegment<3>(x, a, b);
    r.point = e.point;
    r.weights << e.weights[0], e.weights[1], 0.0;
    r.squaredDistance = e.squaredDistance;
  }
  if (testBC)
  {
    const auto e = ClosestPointOnSegment<3>(x, b, c);
    if (e.squaredDistance < r.squaredDistance)
    {
      r.point = e.point;
      r.weights << 0.0, e.weights[0], e.weights[1];
      r.squaredDistance = e.squaredDistance;
    }
  }
  if (testCA)
  {
    const auto e = ClosestPointOnSegment<3>(x, c, a);
    if (e.squaredDistance < r.squaredDistance)
    {
      r.point = e.point;
      r.weights << e.weights[1], 0.0, e.weights[0];
      r.squaredDistance = e.squaredDistance;
    }
  }
  return r;
}

/// Squared distance to triangle (a, b, c); identical to
/// ClosestPointOnTriangle(x, a, b, c).squaredDistance (same arithmetic).
inline double SquaredDistanceToTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c)
{
  return ClosestPointOnTriangle(x, a, b, c).squaredDistance;
}
} // namespace gridfree

#endif
