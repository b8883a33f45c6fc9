// 2D boundaries made of cubic Bézier curves (diffusion curves), and the
// closest point on one cubic Bézier curve.
//
// Closest point on one curve. The squared distance f(t) = |B(t) − x|² is a
// degree-6 polynomial; its interior minima are roots of the quintic
// g(t) = (B(t) − x)·B'(t) = f'(t)/2. Instead of asking a generic root finder
// for all roots (ill-conditioned exactly where it matters: near-equal minima,
// multiple roots at a centre of curvature, degenerate curves), the parameter
// interval is searched by Bézier subdivision (branch and bound):
//
// * Everything is computed relative to the query (control points P − x), so
//   that 1e6 offsets cost no precision: the distance only depends on
//   differences of nearby coordinates.
// * A sub-curve lies in the convex hull of its control points, so the box of
//   those points and a half-plane through them (normal along the chord
//   midpoint direction, a bound that is second-order accurate) give a lower
//   bound of f over the sub-interval. Sub-intervals that cannot beat the best
//   value found so far are discarded.
// * The Bernstein coefficients of g over a sub-interval are products of the
//   sub-curve's control points and its control-point differences. Their number
//   of sign changes bounds the number of roots (Descartes' rule in Bernstein
//   form): none means f is monotone there, so its minimum is at an end point,
//   which was already evaluated; exactly one, going from − to +, isolates a
//   single minimum, which safeguarded Newton on g (bisection fallback, the
//   bracket always kept) converges to; + to − is a maximum. Otherwise the
//   interval is split in half.
// * Every candidate (the ends 0 and 1, every split point, every Newton root)
//   is evaluated on the ORIGINAL curve, so the result is always a true point
//   of the curve: the returned distance can never be below the true minimum
//   (up to the rounding of one evaluation). Subdivided control points are only
//   used for bounds and signs, where their rounding can at worst keep a
//   sub-interval alive longer or drop one whose minimum is within rounding
//   noise of the best value.
// * Degenerate inputs need no special case: a point curve has g ≡ 0 (no sign
//   change, the end point is the answer); lines, cusps and loops are ordinary
//   polynomials for the subdivision. A double root of g (a flat minimum seen
//   from a centre of curvature) never reduces to one sign change: it is ended
//   by the lower bound (sub-intervals within a relative 1e-12 of the best
//   squared distance are not refined further) or a depth limit.
//
// The boundary: BezierBoundaryGeometry puts the curves in a binary BVH over
// their control-point boxes (binned SAH build, O(n log n)), traversed nearest
// child first with box pruning; a curve's root finder only runs when its box
// is closer than the best distance so far, and starts with that bound.
// Queries are const and allocation free: one object can serve many threads.
#ifndef GRIDFREE_GEOMETRY_BEZIER_CURVES_H
#define GRIDFREE_GEOMETRY_BEZIER_CURVES_H

#include <gridfree/geometry/BoundaryGeometry.h>
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/ClosestPointResult.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
/// A cubic Bézier curve B(t) = Σ b_i(t) P[i], t in [0, 1].
struct CubicBezier
{
  Vec2 P[4];

  Vec2 Evaluate(double t) const
  {
    const double s = 1.0 - t;
    return (s * s * s) * this->P[0] + (3.0 * s * s * t) * this->P[1] +
      (3.0 * s * t * t) * this->P[2] + (t * t * t) * this->P[3];
  }

  /// B'(t) = 3 Σ b2_i(t) (P[i+1] − P[i]).
  Vec2 Derivative(double t) const
  {
    const double s = 1.0 - t;
    return 3.0 *
      ((s * s) * (this->P[1] - this->P[0]) + (2.0 * s * t) * (this->P[2] - this->P[1]) +
        (t * t) * (this->P[3] - this->P[2]));
  }

  /// B''(t) = 6 ((1 − t)(P0 − 2 P1 + P2) + t (P1 − 2 P2 + P3)).
  Vec2 SecondDerivative(double t) const
  {
    const Vec2 e0 = (this->P[2] - this->P[1]) - (this->P[1] - this->P[0]);
    const Vec2 e1 = (this->P[3] - this->P[2]) - (this->P[2] - this->P[1]);
    return 6.0 * ((1.0 - t) * e0 + t * e1);
  }

  /// Box of the control points; holds the whole curve (convex hull property).
  BoundingBox<2> ControlBox() const
  {
    BoundingBox<2> box;
    for (const Vec2& p : this->P)
    {
      box.Expand(p);
    }
    return box;
  }

  /// Unit left normal (−dy, dx)/|B'(t)|. Where B' vanishes (a cusp, or an end
  /// with a repeated control point) the tangent is the limit of B' from the
  /// inside of the curve, taken at nearby parameters; then the chord and any
  /// control-point difference. Zero only when all control points coincide.
  Vec2 Normal(double t) const
  {
    double size = 0.0;
    for (int i = 1; i < 4; ++i)
    {
      size = std::max(size, (this->P[i] - this->P[0]).norm());
    }
    if (!(size > 0.0))
    {
      return Vec2::Zero();
    }
    // Below this, B' is rounding noise of the control-point differences.
    const double tiny = 1e-10 * size;
    auto leftNormal = [](const Vec2& d) { return Vec2(Vec2(-d[1], d[0]) / d.norm()); };
    Vec2 d = this->Derivative(t);
    if (d.norm() > tiny)
    {
      return leftNormal(d);
    }
    // Step towards the inside: near t = 0 the tangent direction is B'(h),
    // near t = 1 it is B'(1 − h), both oriented along increasing t.
    for (double h : { 1e-8, 1e-6, 1e-4, 1e-2, 1e-1 })
    {
      d = this->Derivative(t <= 0.5 ? t + h : t - h);
      if (d.norm() > tiny)
      {
        return leftNormal(d);
      }
    }
    d = this->P[3] - this->P[0];
    if (d.norm() > tiny)
    {
      return leftNormal(d);
    }
    for (int i = 1; i < 4; ++i)
    {
      d = this->P[i] - this->P[0];
      if (d.norm() > tiny)
      {
        return leftNormal(d);
      }
    }
    return Vec2::Zero();
  }
};

/// Closest point of one curve: parameter, point B(t) and |x − B(t)|².
struct BezierClosestPoint
{
  double t = 0.0;
  Vec2 point = Vec2::Constant(std::numeric_limits<double>::infinity());
  double squaredDistance = std::numeric_limits<double>::infinity();
};

namespace detail
{
/// Lower bound of |p|² over the convex hull of 4 points (the query is the
/// origin): the larger of the distances to their box and to the half-plane
/// {p·u >= min_i C_i·u}, u along the chord midpoint. The box bound is only
/// first-order accurate for a slanted sub-curve; the half-plane one is
/// second-order once the sub-curve is small, which is what lets the search
/// stop refining around flat minima.
inline double HullSquaredDistanceLowerBound(const Vec2 (&c)[4])
{
  double lo0 = c[0][0], hi0 = c[0][0], lo1 = c[0][1], hi1 = c[0][1];
  for (int i = 1; i < 4; ++i)
  {
    lo0 = std::min(lo0, c[i][0]);
    hi0 = std::max(hi0, c[i][0]);
    lo1 = std::min(lo1, c[i][1]);
    hi1 = std::max(hi1, c[i][1]);
  }
  const double g0 = std::max(std::max(lo0, -hi0), 0.0);
  const double g1 = std::max(std::max(lo1, -hi1), 0.0);
  double bound = g0 * g0 + g1 * g1;
  const Vec2 u = c[0] + c[3];
  const double n = u.norm();
  if (n > 0.0)
  {
    double m = c[0].dot(u);
    for (int i = 1; i < 4; ++i)
    {
      m = std::min(m, c[i].dot(u));
    }
    if (m > 0.0)
    {
      // Divide after the minimum: one rounding instead of four.
      m /= n;
      bound = std::max(bound, m * m);
    }
  }
  return bound;
}

/// Branch-and-bound search for the global minimum of |B(t) − x|² over
/// [0, 1] (see the file comment). Start with Best2 = an upper bound already
/// known (e.g. from other curves) to prune everything that cannot beat it.
class CubicBezierSearch
{
public:
  CubicBezierSearch(const Vec2& x, const CubicBezier& c, double bound2)
    : Best2(bound2)
  {
    for (int i = 0; i < 4; ++i)
    {
      this->Q[i] = c.P[i] - x;
    }
    for (int i = 0; i < 3; ++i)
    {
      this->D[i] = c.P[i + 1] - c.P[i];
    }
    for (int i = 0; i < 2; ++i)
    {
      this->E[i] = this->D[i + 1] - this->D[i];
    }
  }

  /// Runs the search; returns true if a value below the initial bound was
  /// found, in which case Best2 and BestT describe it.
  bool Run();

  double Best2;
  double BestT = 0.0;
  bool Found = false;

private:
  // Below this many subdivisions (width 2^-48 in t) an interval is simply
  // sampled at its midpoint: it can only be there because of a multiple root
  // of g, where f is flat, or rounding noise.
  static constexpr int kMaxDepth = 48;
  // Sub-intervals whose bound is within this relative amount of the best
  // squared distance are not refined: they could only improve the distance
  // by half of it, relatively (5e-13).
  static constexpr double kRelativeSlack = 1e-12;

  struct Interval
  {
    double A;
    double B;
    Vec2 C[4]; // control points of the sub-curve over [A, B], relative to x
    double Bound;
    int Depth;
  };

  /// B(t) − x.
  Vec2 Relative(double t) const
  {
    const double s = 1.0 - t;
    return (s * s * s) * this->Q[0] + (3.0 * s * s * t) * this->Q[1] +
      (3.0 * s * t * t) * this->Q[2] + (t * t * t) * this->Q[3];
  }

  /// g(t) = (B − x)·B' and g'(t) = |B'|² + (B − x)·B'' (B' and B'' divided
  /// by 3, which changes neither the roots nor the Newton steps), and a bound
  /// of the rounding error of g: the error of B − x is relative to the
  /// largest Q, the error of B' to the largest D, and each is multiplied by
  /// the other factor of the dot product. Near a cusp both B' and the error of
  /// g are small, so the bound must depend on t.
  void Stationarity(double t, double qmax, double dmax, double& g, double& dg, double& noise) const
  {
    const double s = 1.0 - t;
    const Vec2 r = this->Relative(t);
    const Vec2 d = (s * s) * this->D[0] + (2.0 * s * t) * this->D[1] + (t * t) * this->D[2];
    const Vec2 e = 2.0 * (s * this->E[0] + t * this->E[1]);
    g = r.dot(d);
    dg = 3.0 * d.squaredNorm() + r.dot(e);
    noise = 16.0 * std::numeric_limits<double>::epsilon() *
      (qmax * d.cwiseAbs().maxCoeff() + r.cwiseAbs().maxCoeff() * dmax);
  }

  void Consider(double t) { this->Consider(t, this->Relative(t).squaredNorm()); }

  void Consider(double t, double f)
  {
    if (f < this->Best2)
    {
      this->Best2 = f;
      this->BestT = t;
      this->Found = true;
    }
  }

  double Newton(double lo, double hi, double glo, double ghi) const;

  Vec2 Q[4]; // control points relative to the query
  Vec2 D[3]; // control-point differences (B'/3 in Bernstein form)
  Vec2 E[2]; // second differences (B''/6)
};

//------------------------------------------------------------------------------
// Safeguarded Newton on g over a bracket with g(lo) <= 0 <= g(hi): a Newton
// step is taken when it stays inside the bracket and at least halves the
// previous step, otherwise the bracket is bisected, so the iteration always
// converges (quadratically at a simple root, at least linearly otherwise).
// It stops once |g| is within its own rounding noise: past that point Newton
// steps are random, and bisecting a bracket whose far side never moved would
// only waste iterations. There, f is within that noise of its minimum.
inline double CubicBezierSearch::Newton(double lo, double hi, double glo, double ghi) const
{
  double qmax = 0.0;
  double dmax = 0.0;
  for (int i = 0; i < 4; ++i)
  {
    qmax = std::max(qmax, this->Q[i].cwiseAbs().maxCoeff());
  }
  for (int i = 0; i < 3; ++i)
  {
    dmax = std::max(dmax, this->D[i].cwiseAbs().maxCoeff());
  }

  double t = 0.5 * (lo + hi);
  if (glo < ghi)
  {
    const double secant = lo - glo * (hi - lo) / (ghi - glo);
    if (secant > lo && secant < hi)
    {
      t = secant;
    }
  }
  double lastStep = hi - lo;
  for (int iter = 0; iter < 100; ++iter)
  {
    double g, dg, noise;
    this->Stationarity(t, qmax, dmax, g, dg, noise);
    if (std::abs(g) <= noise)
    {
      return t;
    }
    if (g < 0.0)
    {
      lo = t;
    }
    else
    {
      hi = t;
    }
    // A NaN step (dg = 0) fails the bracket test and bisects.
    double next = t - g / dg;
    if (!(next > lo && next < hi) || std::abs(next - t) > 0.5 * lastStep)
    {
      next = 0.5 * (lo + hi);
    }
    const double step = std::abs(next - t);
    if (step <= 1e-16)
    {
      return next;
    }
    lastStep = step;
    t = next;
  }
  return t;
}

//------------------------------------------------------------------------------
inline bool CubicBezierSearch::Run()
{
  // Most curves that reach this point from a BVH are still too far: the hull
  // bound is checked before anything else is evaluated.
  const double rootBound = HullSquaredDistanceLowerBound(this->Q);
  if (rootBound >= this->Best2 * (1.0 - kRelativeSlack))
  {
    return false;
  }
  // The ends: B(0) − x = Q[0] and B(1) − x = Q[3] exactly.
  this->Consider(0.0, this->Q[0].squaredNorm());
  this->Consider(1.0, this->Q[3].squaredNorm());

  // Depth-first, nearer half first: each level leaves at most one pending
  // sibling, so kMaxDepth + 1 entries always suffice.
  Interval stack[kMaxDepth + 2];
  int top = 0;
  {
    Interval& root = stack[top++];
    root.A = 0.0;
    root.B = 1.0;
    for (int i = 0; i < 4; ++i)
    {
      root.C[i] = this->Q[i];
    }
    root.Bound = rootBound;
    root.Depth = 0;
  }

  while (top > 0)
  {
    // A reference is safe: the slot is only overwritten by the final pushes,
    // after the children were computed.
    const Interval& iv = stack[--top];
    if (iv.Bound >= this->Best2 * (1.0 - kRelativeSlack))
    {
      continue;
    }

    // Bernstein coefficients of g over the sub-interval, up to positive
    // factors (the binomial weights of the product and the interval width).
    const Vec2 d0 = iv.C[1] - iv.C[0];
    const Vec2 d1 = iv.C[2] - iv.C[1];
    const Vec2 d2 = iv.C[3] - iv.C[2];
    const double h[6] = { iv.C[0].dot(d0), 3.0 * iv.C[1].dot(d0) + 2.0 * iv.C[0].dot(d1),
      3.0 * iv.C[2].dot(d0) + 6.0 * iv.C[1].dot(d1) + iv.C[0].dot(d2),
      iv.C[3].dot(d0) + 6.0 * iv.C[2].dot(d1) + 3.0 * iv.C[1].dot(d2),
      2.0 * iv.C[3].dot(d1) + 3.0 * iv.C[2].dot(d2), iv.C[3].dot(d2) };
    int changes = 0;
    int first = 0;
    int previous = 0;
    for (double v : h)
    {
      const int sign = (v > 0.0) - (v < 0.0);
      if (sign == 0)
      {
        continue; // zeros do not count in Descartes' rule
      }
      if (first == 0)
      {
        first = sign;
      }
      else if (sign != previous)
      {
        ++changes;
      }
      previous = sign;
    }
    if (changes == 0)
    {
      continue; // f monotone: its minimum is at an end, already evaluated
    }
    if (changes == 1)
    {
      if (first > 0)
      {
        continue; // a single maximum of f
      }
      // A single minimum, bracketed by the ends: h[0] and h[5] are g at the
      // ends times the same positive factor, which is all the secant start
      // and the bracket need. Newton evaluates g on the original curve, so
      // any rounding in these signs only costs iterations.
      this->Consider(this->Newton(iv.A, iv.B, h[0], h[5]));
      continue;
    }
    if (iv.Depth >= kMaxDepth)
    {
      this->Consider(0.5 * (iv.A + iv.B));
      continue;
    }

    // Split at the middle (de Casteljau with weights 1/2 is exact up to one
    // rounding per point) and evaluate the split point on the original curve.
    const double m = 0.5 * (iv.A + iv.B);
    this->Consider(m);
    Interval left, right;
    left.A = iv.A;
    left.B = m;
    right.A = m;
    right.B = iv.B;
    left.Depth = right.Depth = iv.Depth + 1;
    const Vec2 a01 = 0.5 * (iv.C[0] + iv.C[1]);
    const Vec2 a12 = 0.5 * (iv.C[1] + iv.C[2]);
    const Vec2 a23 = 0.5 * (iv.C[2] + iv.C[3]);
    const Vec2 b0 = 0.5 * (a01 + a12);
    const Vec2 b1 = 0.5 * (a12 + a23);
    const Vec2 mid = 0.5 * (b0 + b1);
    left.C[0] = iv.C[0];
    left.C[1] = a01;
    left.C[2] = b0;
    left.C[3] = mid;
    right.C[0] = mid;
    right.C[1] = b1;
    right.C[2] = a23;
    right.C[3] = iv.C[3];
    left.Bound = HullSquaredDistanceLowerBound(left.C);
    right.Bound = HullSquaredDistanceLowerBound(right.C);
    const double cut = this->Best2 * (1.0 - kRelativeSlack);
    const bool keepLeft = left.Bound < cut;
    const bool keepRight = right.Bound < cut;
    if (keepLeft && keepRight)
    {
      // The farther half goes first onto the stack, so it is popped last.
      if (left.Bound <= right.Bound)
      {
        stack[top++] = right;
        stack[top++] = left;
      }
      else
      {
        stack[top++] = left;
        stack[top++] = right;
      }
    }
    else if (keepLeft)
    {
      stack[top++] = left;
    }
    else if (keepRight)
    {
      stack[top++] = right;
    }
  }
  return this->Found;
}
} // namespace detail

/// Global minimum of |x − B(t)|² over t in [0, 1]. Robust for any finite
/// curve (see the file comment); `point` is c.Evaluate(t), the squared
/// distance is computed relative to x, so it keeps full precision at large
/// coordinates.
inline BezierClosestPoint ClosestPointOnCubicBezier(const Vec2& x, const CubicBezier& c)
{
  detail::CubicBezierSearch search(x, c, std::numeric_limits<double>::infinity());
  search.Run();
  BezierClosestPoint result;
  result.t = search.BestT;
  result.point = c.Evaluate(search.BestT);
  result.squaredDistance = search.Best2;
  return result;
}

/// Cheap lower bound of the squared distance from x to the curve: the
/// squared distance to the box of its control points, which holds the curve.
inline double SquaredDistanceToCubicBezierLowerBound(const Vec2& x, const CubicBezier& c)
{
  return c.ControlBox().SquaredDistance(x);
}

//------------------------------------------------------------------------------
/// A Dirichlet boundary made of cubic Bézier curves. ClosestPointResult:
/// `primitive` = curve index, `barycentric` = (1 − t, t), the weights of the
/// curve's first and last control points.
class BezierBoundaryGeometry final : public BoundaryGeometry<2>
{
public:
  /// Builds the BVH; O(n log n). Throws std::invalid_argument for a
  /// non-finite control point. An empty set is a boundary at infinity.
  explicit BezierBoundaryGeometry(std::vector<CubicBezier> curves);

  /// Exact distance to the nearest curve (up to rounding); inf if empty.
  double Distance(const Vec2& x) const override
  {
    std::int64_t curve;
    double t;
    return std::sqrt(this->FindNearest(x, curve, t));
  }

  ClosestPointResult<2> ClosestPoint(const Vec2& x) const override
  {
    ClosestPointResult<2> result;
    std::int64_t curve;
    double t;
    const double best2 = this->FindNearest(x, curve, t);
    if (curve < 0)
    {
      return result;
    }
    result.point = this->CurveList[curve].Evaluate(t);
    result.distance = std::sqrt(best2);
    result.primitive = curve;
    result.barycentric = Vec2(1.0 - t, t);
    return result;
  }

  /// Left normal of the hit's curve at t = barycentric[1] (see
  /// CubicBezier::Normal); zero for an invalid hit or a point curve.
  Vec2 Normal(const ClosestPointResult<2>& hit) const override
  {
    if (hit.primitive < 0 || hit.primitive >= this->NumberOfParts())
    {
      return Vec2::Zero();
    }
    const double t = hit.barycentric[1];
    return this->CurveList[hit.primitive].Normal(t >= 0.0 ? std::min(t, 1.0) : 0.0);
  }

  BoundingBox<2> Bounds() const override { return this->Box; }

  /// Whether x is enclosed by closed curves: the parity of the crossings of
  /// the ray toward +x with each curve drawn as kEnclosureSegments chords
  /// (off by at most the chords' sag, a few 10⁻⁵ of a quarter circle's
  /// radius). Open curves enclose nothing well defined.
  bool Encloses(const Vec2& x) const override
  {
    bool inside = false;
    for (const CubicBezier& curve : this->CurveList)
    {
      Vec2 a = curve.P[0];
      for (int i = 1; i <= kEnclosureSegments; ++i)
      {
        const Vec2 b = curve.Evaluate(static_cast<double>(i) / kEnclosureSegments);
        if ((a[1] > x[1]) != (b[1] > x[1]) &&
          x[0] < a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
        {
          inside = !inside;
        }
        a = b;
      }
    }
    return inside;
  }
  static constexpr int kEnclosureSegments = 64;

  std::int64_t NumberOfParts() const override
  {
    return static_cast<std::int64_t>(this->CurveList.size());
  }

  const std::vector<CubicBezier>& Curves() const { return this->CurveList; }

private:
  /// Child reference: >= 0 an internal node, < 0 the curve ~ref (every leaf
  /// holds one curve, so a child box is that curve's control box and the
  /// root finder never runs for a curve whose box is too far).
  using Ref = std::int32_t;

  struct Node
  {
    double Lo[2][2]; // [child][axis]
    double Hi[2][2];
    Ref Child[2];
  };

  // Below this tree level the builder uses median splits, which bounds the
  // depth for any input (counts < 2^31 halve at every median level).
  static constexpr int kMaxSahLevel = 32;
  static constexpr int kStackSize = kMaxSahLevel + 34;

  struct BuildState
  {
    std::vector<BoundingBox<2>> Boxes;
    std::vector<Vec2> Centers;
    std::vector<std::int32_t> Order;
  };

  Ref Build(BuildState& s, std::int32_t begin, std::int32_t end, int level, BoundingBox<2>& box);

  static double BoxSquaredDistance(const double lo[2], const double hi[2], const Vec2& x)
  {
    const double g0 = std::max(std::max(lo[0] - x[0], x[0] - hi[0]), 0.0);
    const double g1 = std::max(std::max(lo[1] - x[1], x[1] - hi[1]), 0.0);
    return g0 * g0 + g1 * g1;
  }

  /// Squared distance to the nearest curve, its index (-1 if none) and t.
  double FindNearest(const Vec2& x, std::int64_t& curve, double& t) const;

  std::vector<CubicBezier> CurveList;
  std::vector<Node> Nodes;
  Ref Root = 0;
  BoundingBox<2> Box;
};

//------------------------------------------------------------------------------
inline BezierBoundaryGeometry::BezierBoundaryGeometry(std::vector<CubicBezier> curves)
  : CurveList(std::move(curves))
{
  const std::size_t n = this->CurveList.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
  {
    throw std::length_error("BezierBoundaryGeometry: too many curves");
  }
  BuildState s;
  s.Boxes.resize(n);
  s.Centers.resize(n);
  s.Order.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (const Vec2& p : this->CurveList[i].P)
    {
      if (!p.allFinite())
      {
        throw std::invalid_argument(
          "BezierBoundaryGeometry: curve " + std::to_string(i) + " has a non-finite control point");
      }
    }
    s.Boxes[i] = this->CurveList[i].ControlBox();
    s.Centers[i] = s.Boxes[i].Center();
    s.Order[i] = static_cast<std::int32_t>(i);
  }
  if (n == 0)
  {
    return;
  }
  this->Nodes.reserve(n);
  this->Root = this->Build(s, 0, static_cast<std::int32_t>(n), 0, this->Box);
}

//------------------------------------------------------------------------------
// Binned surface area heuristic (perimeter in 2D) over box centers on both
// axes; object median along the longest axis when the SAH has no split or the
// tree got deep. Nodes are stored depth first.
inline BezierBoundaryGeometry::Ref BezierBoundaryGeometry::Build(
  BuildState& s, std::int32_t begin, std::int32_t end, int level, BoundingBox<2>& box)
{
  box = BoundingBox<2>();
  if (end - begin == 1)
  {
    box = s.Boxes[s.Order[begin]];
    return ~s.Order[begin];
  }
  BoundingBox<2> centers;
  for (std::int32_t i = begin; i < end; ++i)
  {
    centers.Expand(s.Centers[s.Order[i]]);
  }
  const Vec2 extent = centers.Extent();
  const std::int32_t n = end - begin;
  std::int32_t mid = -1;

  if (level < kMaxSahLevel)
  {
    constexpr int kBins = 16;
    double bestCost = std::numeric_limits<double>::infinity();
    int bestAxis = -1;
    int bestBin = -1;
    for (int axis = 0; axis < 2; ++axis)
    {
      if (!(extent[axis] > 0.0))
      {
        continue;
      }
      const double lo = centers.Min[axis];
      const double scale = kBins / extent[axis];
      std::int32_t counts[kBins] = {};
      BoundingBox<2> boxes[kBins];
      for (std::int32_t i = begin; i < end; ++i)
      {
        const std::int32_t id = s.Order[i];
        const int b = std::min(kBins - 1, static_cast<int>((s.Centers[id][axis] - lo) * scale));
        counts[b]++;
        boxes[b].Expand(s.Boxes[id]);
      }
      double rightCost[kBins];
      BoundingBox<2> acc;
      std::int32_t count = 0;
      for (int b = kBins - 1; b > 0; --b)
      {
        acc.Expand(boxes[b]);
        count += counts[b];
        rightCost[b] = count ? acc.HalfArea() * count : 0.0;
      }
      acc = BoundingBox<2>();
      count = 0;
      for (int b = 1; b < kBins; ++b)
      {
        acc.Expand(boxes[b - 1]);
        count += counts[b - 1];
        if (count == 0 || count == n)
        {
          continue;
        }
        const double cost = acc.HalfArea() * count + rightCost[b];
        if (cost < bestCost)
        {
          bestCost = cost;
          bestAxis = axis;
          bestBin = b;
        }
      }
    }
    if (bestAxis >= 0)
    {
      const double lo = centers.Min[bestAxis];
      const double scale = kBins / extent[bestAxis];
      const auto it = std::partition(s.Order.begin() + begin, s.Order.begin() + end,
        [&](std::int32_t id) {
          return std::min(kBins - 1, static_cast<int>((s.Centers[id][bestAxis] - lo) * scale)) <
            bestBin;
        });
      mid = static_cast<std::int32_t>(it - s.Order.begin());
    }
  }
  if (mid <= begin || mid >= end)
  {
    const int axis = centers.LongestAxis();
    mid = begin + n / 2;
    std::nth_element(s.Order.begin() + begin, s.Order.begin() + mid, s.Order.begin() + end,
      [&](std::int32_t p, std::int32_t q) { return s.Centers[p][axis] < s.Centers[q][axis]; });
  }

  const auto index = static_cast<Ref>(this->Nodes.size());
  this->Nodes.emplace_back();
  BoundingBox<2> childBox[2];
  // Recursion reallocates Nodes: compute the children before storing them.
  const Ref left = this->Build(s, begin, mid, level + 1, childBox[0]);
  const Ref right = this->Build(s, mid, end, level + 1, childBox[1]);
  Node& node = this->Nodes[index];
  node.Child[0] = left;
  node.Child[1] = right;
  for (int c = 0; c < 2; ++c)
  {
    for (int k = 0; k < 2; ++k)
    {
      node.Lo[c][k] = childBox[c].Min[k];
      node.Hi[c][k] = childBox[c].Max[k];
    }
    box.Expand(childBox[c]);
  }
  return index;
}

//------------------------------------------------------------------------------
// Nearest child first with an explicit stack. Box distances are exact lower
// bounds up to one rounding, so only curves that could tie within rounding
// with the best one are ever skipped.
inline double BezierBoundaryGeometry::FindNearest(
  const Vec2& x, std::int64_t& curve, double& t) const
{
  double best2 = std::numeric_limits<double>::infinity();
  curve = -1;
  t = 0.0;
  if (this->CurveList.empty())
  {
    return best2;
  }
  struct Entry
  {
    Ref Target;
    double Dist2;
  };
  Entry stack[kStackSize];
  int top = 0;
  stack[top++] = Entry{ this->Root, this->Box.SquaredDistance(x) };
  while (top > 0)
  {
    const Entry entry = stack[--top];
    if (entry.Dist2 >= best2)
    {
      continue;
    }
    Ref ref = entry.Target;
    for (;;)
    {
      if (ref < 0)
      {
        const std::int32_t id = ~ref;
        detail::CubicBezierSearch search(x, this->CurveList[id], best2);
        if (search.Run())
        {
          best2 = search.Best2;
          curve = id;
          t = search.BestT;
        }
        break;
      }
      const Node& node = this->Nodes[ref];
      const double d0 = BoxSquaredDistance(node.Lo[0], node.Hi[0], x);
      const double d1 = BoxSquaredDistance(node.Lo[1], node.Hi[1], x);
      const bool visit0 = d0 < best2;
      const bool visit1 = d1 < best2;
      if (visit0 && visit1)
      {
        const bool nearFirst = d0 <= d1;
        stack[top++] = nearFirst ? Entry{ node.Child[1], d1 } : Entry{ node.Child[0], d0 };
        ref = nearFirst ? node.Child[0] : node.Child[1];
      }
      else if (visit0)
      {
        ref = node.Child[0];
      }
      else if (visit1)
      {
        ref = node.Child[1];
      }
      else
      {
        break;
      }
    }
  }
  return best2;
}
} // namespace gridfree

#endif
