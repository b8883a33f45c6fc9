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
#ifndef GRIDFREE_GEOMETRY_CLOSEST_POINT_PRIMITIVES_H
#define GRIDFREE_GEOMETRY_CLOSEST_POINT_PRIMITIVES_H

#include <gridfree/math/Vector.h>

#include <Eigen/Geometry> // cross product

#include <cmath>
#include <limits>
#include <vector>

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
inline Vec<DIM> SegmentPoint(double t, const Vec<DIM>& a, const Vec<DIM>& b, const Vec<DIM>& ab)
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

namespace detail
{
/// Edge vectors and normal of triangle (a, b, c), shared by the kernels.
struct TriangleFrame
{
  Vec3 ab, ac, n;
  double nn;     // |n|^2 = |ab|^2 |ac|^2 sin^2(angle at a)
  double ab2ac2; // |ab|^2 |ac|^2
  bool degenerate;

  TriangleFrame(const Vec3& a, const Vec3& b, const Vec3& c)
    : ab(b - a)
    , ac(c - a)
    , n(ab.cross(ac))
    , nn(n.squaredNorm())
    , ab2ac2(ab.squaredNorm() * ac.squaredNorm())
    // Written so that NaN input counts as degenerate (edge path, no division).
    , degenerate(!(nn > kDegenerateTriangleSin2 * ab2ac2))
  {
  }
};

inline PrimitiveClosestPoint<3, 3> TriangleClosestPoint(
  const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const TriangleFrame& f)
{
  PrimitiveClosestPoint<3, 3> r;
  // Edge candidates; each flag is set for edges that may hold the answer.
  bool testBC = true, testCA = true, testAB = true;
  if (!f.degenerate)
  {
    const Vec3 ap = x - a;
    const double inv = 1.0 / f.nn;
    const double v = ap.dot(f.ac.cross(f.n)) * inv;
    const double w = ap.dot(f.n.cross(f.ab)) * inv;
    const double u = 1.0 - v - w;
    if (u >= 0.0 && v >= 0.0 && w >= 0.0)
    {
      r.point = a + v * f.ab + w * f.ac;
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
} // namespace detail

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
  return detail::TriangleClosestPoint(x, a, b, c, detail::TriangleFrame(a, b, c));
}

/// Squared distance to triangle (a, b, c); identical to
/// ClosestPointOnTriangle(x, a, b, c).squaredDistance (same arithmetic).
inline double SquaredDistanceToTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c)
{
  return ClosestPointOnTriangle(x, a, b, c).squaredDistance;
}

/// Squared distance to triangle (a, b, c) for a search that only needs
/// distances below sqrt(bound2): returns +inf early when the distance to the
/// triangle's plane, a lower bound, already exceeds it. Otherwise the result
/// is SquaredDistanceToTriangle(x, a, b, c).
///
/// This is what makes queries from deep inside a closed surface affordable:
/// there, many triangles are nearly equidistant, their boxes cannot be pruned,
/// but the plane test rejects them at a fraction of the full cost. The test
/// allows for its own rounding: the computed s = ap . n is within
/// 11 eps |ap| |ab| |ac| of the exact value, which the margin below covers
/// (using 2 e sqrt(B) <= 2^-20 B + 2^20 e^2 to avoid square roots).
inline double SquaredDistanceToTriangle(
  const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double bound2)
{
  const detail::TriangleFrame f(a, b, c);
  if (!f.degenerate)
  {
    const Vec3 ap = x - a;
    const double s = ap.dot(f.n);
    if (s * s > f.nn * bound2 * (1.0 + 0x1p-20) + 0x1p-76 * ap.squaredNorm() * f.ab2ac2)
    {
      return std::numeric_limits<double>::infinity();
    }
  }
  return detail::TriangleClosestPoint(x, a, b, c, f).squaredDistance;
}

/// Unit normal of the simplex `ids` of `vertices` in its vertex order
/// (segment: left normal; triangle: right-handed); zero for a degenerate one.
template <int DIM, typename Ids>
Vec<DIM> SimplexUnitNormal(const std::vector<Vec<DIM>>& vertices, const Ids& ids)
{
  Vec<DIM> n = Vec<DIM>::Zero();
  if constexpr (DIM == 2)
  {
    const Vec<DIM> e = vertices[ids[1]] - vertices[ids[0]];
    n << -e[1], e[0];
  }
  else
  {
    n = (vertices[ids[1]] - vertices[ids[0]]).cross(vertices[ids[2]] - vertices[ids[0]]);
  }
  const double length = n.norm();
  return length > 0.0 && std::isfinite(length) ? Vec<DIM>(n / length) : Vec<DIM>::Zero();
}
} // namespace gridfree

#endif
