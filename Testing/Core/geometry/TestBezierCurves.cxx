// Tests of the closest point on cubic Bézier curves and of the Bézier-curve
// boundary geometry.
//
// The single-curve search is compared with an independent reference: dense
// uniform sampling of the parameter refined by golden-section search around
// the best sampled local minima. The search must never be worse than that
// reference (beyond 1e-10 of the scale), and its answer must be a true point
// of the curve, so it can never be better than the true minimum either. The
// boundary geometry must agree with a brute-force minimum over all curves.
// Seeds are fixed, so failures are reproducible.
#include <gridfree/geometry/BezierCurves.h>
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/math/Vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{
using gridfree::BezierBoundaryGeometry;
using gridfree::ClosestPointOnCubicBezier;
using gridfree::CubicBezier;
using gridfree::Vec2;

constexpr double kInf = std::numeric_limits<double>::infinity();

CubicBezier MakeCurve(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3)
{
  CubicBezier c;
  c.P[0] = p0;
  c.P[1] = p1;
  c.P[2] = p2;
  c.P[3] = p3;
  return c;
}

/// B(t) − x evaluated from the control points relative to x, the most
/// accurate way to get a distance when coordinates are large.
Vec2 RelativePoint(const CubicBezier& c, const Vec2& x, double t)
{
  const double s = 1.0 - t;
  return (s * s * s) * (c.P[0] - x) + (3.0 * s * s * t) * (c.P[1] - x) +
    (3.0 * s * t * t) * (c.P[2] - x) + (t * t * t) * (c.P[3] - x);
}

double Size(const CubicBezier& c)
{
  return c.ControlBox().Diagonal();
}

double Magnitude(const CubicBezier& c, const Vec2& x)
{
  double m = x.cwiseAbs().maxCoeff();
  for (const Vec2& p : c.P)
  {
    m = std::max(m, p.cwiseAbs().maxCoeff());
  }
  return m;
}

struct Reference
{
  double SquaredDistance = kInf;
  double T = 0.0;
};

//------------------------------------------------------------------------------
// Dense reference: 20,000 uniform samples, then golden-section refinement of
// f on the two sample intervals around each of the best sampled local minima.
Reference DenseMinimum(const Vec2& x, const CubicBezier& c, int samples = 20000)
{
  auto f = [&](double t) { return RelativePoint(c, x, t).squaredNorm(); };
  std::vector<double> values(samples + 1);
  for (int i = 0; i <= samples; ++i)
  {
    values[i] = f(static_cast<double>(i) / samples);
  }
  std::vector<std::pair<double, int>> minima;
  for (int i = 0; i <= samples; ++i)
  {
    const bool leftOk = i == 0 || values[i] <= values[i - 1];
    const bool rightOk = i == samples || values[i] <= values[i + 1];
    if (leftOk && rightOk)
    {
      minima.emplace_back(values[i], i);
    }
  }
  std::sort(minima.begin(), minima.end());
  Reference best;
  for (const auto& m : minima)
  {
    if (m.first < best.SquaredDistance)
    {
      best.SquaredDistance = m.first;
      best.T = static_cast<double>(m.second) / samples;
    }
  }
  const std::size_t refine = std::min<std::size_t>(minima.size(), 8);
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  for (std::size_t k = 0; k < refine; ++k)
  {
    const int i = minima[k].second;
    double a = static_cast<double>(std::max(i - 1, 0)) / samples;
    double b = static_cast<double>(std::min(i + 1, samples)) / samples;
    double c1 = b - phi * (b - a);
    double c2 = a + phi * (b - a);
    double f1 = f(c1);
    double f2 = f(c2);
    for (int iter = 0; iter < 80; ++iter)
    {
      if (f1 <= f2)
      {
        b = c2;
        c2 = c1;
        f2 = f1;
        c1 = b - phi * (b - a);
        f1 = f(c1);
      }
      else
      {
        a = c1;
        c1 = c2;
        f1 = f2;
        c2 = a + phi * (b - a);
        f2 = f(c2);
      }
    }
    for (double t : { c1, c2 })
    {
      const double v = f(t);
      if (v < best.SquaredDistance)
      {
        best.SquaredDistance = v;
        best.T = t;
      }
    }
  }
  return best;
}

//------------------------------------------------------------------------------
// The search is never worse than the dense reference and returns a true point
// of the curve with a consistent distance.
void CheckAgainstDense(const Vec2& x, const CubicBezier& c, int samples = 20000)
{
  const gridfree::BezierClosestPoint r = ClosestPointOnCubicBezier(x, c);
  const Reference ref = DenseMinimum(x, c, samples);
  const double dref = std::sqrt(ref.SquaredDistance);
  const double d = std::sqrt(r.squaredDistance);
  const double scale = std::max(Size(c), dref);
  const double magnitude = Magnitude(c, x);

  ASSERT_TRUE(r.t >= 0.0 && r.t <= 1.0) << r.t;
  EXPECT_LE(d, dref + 1e-10 * scale) << "x = " << x.transpose() << " t = " << r.t
                                     << " ref t = " << ref.T;
  // On the curve: the point is B(t), and the distance is |x − B(t)|.
  EXPECT_LE((c.Evaluate(r.t) - r.point).norm(), 1e-15 * magnitude);
  EXPECT_NEAR(r.squaredDistance, RelativePoint(c, x, r.t).squaredNorm(), 1e-14 * scale * scale);
  EXPECT_NEAR(d, (x - r.point).norm(), 1e-13 * scale + 1e-15 * magnitude);
}

/// Queries around a curve: random points in and around its control box, the
/// control points themselves, points on the curve, slightly off the curve
/// along the normal, and centres of curvature.
std::vector<Vec2> QueriesAround(const CubicBezier& c, std::mt19937_64& rng, int count)
{
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const gridfree::BoundingBox<2> box = c.ControlBox();
  const double size = std::max(box.Diagonal(), 1e-300);
  std::vector<Vec2> queries;
  for (int i = 0; i < count; ++i)
  {
    queries.push_back(box.Center() +
      Vec2(u01(rng) - 0.5, u01(rng) - 0.5).cwiseProduct(2.0 * box.Extent() + Vec2::Constant(size)));
  }
  for (const Vec2& p : c.P)
  {
    queries.push_back(p);
  }
  for (int i = 0; i < count; ++i)
  {
    const double t = u01(rng);
    const Vec2 b = c.Evaluate(t);
    queries.push_back(b);
    const Vec2 d = c.Derivative(t);
    if (d.norm() > 1e-12 * size)
    {
      const Vec2 n(-d[1] / d.norm(), d[0] / d.norm());
      queries.push_back(b + (u01(rng) - 0.5) * 1e-6 * size * n);
      // Centre of curvature: every nearby curve point is at nearly the
      // same distance.
      const Vec2 dd = c.SecondDerivative(t);
      const double cross = d[0] * dd[1] - d[1] * dd[0];
      if (std::abs(cross) > 1e-12 * d.squaredNorm() * dd.norm())
      {
        const double radius = d.squaredNorm() * d.norm() / cross; // signed
        if (std::abs(radius) < 1e3 * size)
        {
          queries.push_back(b + radius * n);
        }
      }
    }
  }
  return queries;
}

void CheckCurve(const CubicBezier& c, std::uint64_t seed, int count = 20, int samples = 20000)
{
  std::mt19937_64 rng(seed);
  for (const Vec2& x : QueriesAround(c, rng, count))
  {
    CheckAgainstDense(x, c, samples);
    if (::testing::Test::HasFailure())
    {
      FAIL() << "curve " << c.P[0].transpose() << " | " << c.P[1].transpose() << " | "
             << c.P[2].transpose() << " | " << c.P[3].transpose();
    }
  }
}

//------------------------------------------------------------------------------
TEST(BezierCurves, EvaluateAndDerivatives)
{
  const CubicBezier c = MakeCurve(Vec2(0, 0), Vec2(1, 2), Vec2(3, -1), Vec2(4, 1));
  EXPECT_EQ(c.Evaluate(0.0), c.P[0]);
  EXPECT_EQ(c.Evaluate(1.0), c.P[3]);
  EXPECT_TRUE(c.Derivative(0.0).isApprox(3.0 * (c.P[1] - c.P[0])));
  EXPECT_TRUE(c.Derivative(1.0).isApprox(3.0 * (c.P[3] - c.P[2])));
  const double h = 1e-6;
  for (double t : { 0.1, 0.37, 0.5, 0.9 })
  {
    const Vec2 fd = (c.Evaluate(t + h) - c.Evaluate(t - h)) / (2 * h);
    EXPECT_LT((fd - c.Derivative(t)).norm(), 1e-8);
    const Vec2 fd2 = (c.Derivative(t + h) - c.Derivative(t - h)) / (2 * h);
    EXPECT_LT((fd2 - c.SecondDerivative(t)).norm(), 1e-7);
  }
}

TEST(BezierCurves, RandomCurvesMatchDenseSampling)
{
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1500; ++i)
  {
    const CubicBezier c =
      MakeCurve(Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)));
    std::vector<Vec2> queries = { Vec2(2 * u(rng), 2 * u(rng)), Vec2(0.5 * u(rng), 0.5 * u(rng)) };
    const double t = 0.5 * (u(rng) + 1.0);
    queries.push_back(c.Evaluate(t));
    for (const Vec2& x : queries)
    {
      CheckAgainstDense(x, c);
    }
    if (HasFailure())
    {
      FAIL() << "curve " << i;
    }
  }
}

TEST(BezierCurves, PointCurve)
{
  const Vec2 p(0.3, -0.7);
  const CubicBezier c = MakeCurve(p, p, p, p);
  for (const Vec2& x : { Vec2(0.3, -0.7), Vec2(1, 2), Vec2(-5, 0.1) })
  {
    const auto r = ClosestPointOnCubicBezier(x, c);
    EXPECT_DOUBLE_EQ(std::sqrt(r.squaredDistance), (x - p).norm());
    EXPECT_EQ(r.point, p);
  }
}

TEST(BezierCurves, LinesWithCoincidentControlPoints)
{
  const Vec2 a(-1, 0.5), b(2, 1.5);
  CheckCurve(MakeCurve(a, a, b, b), 1);
  CheckCurve(MakeCurve(a, a, a, b), 2);
  CheckCurve(MakeCurve(a, b, b, b), 3);
  CheckCurve(MakeCurve(a, b, a, b), 4);
  CheckCurve(MakeCurve(a, a, b, a), 5); // out and back
}

TEST(BezierCurves, NonUniformStraightSegments)
{
  // Collinear control points out of order: the curve overshoots its end
  // points and runs back, so the parameter is far from arc length.
  CheckCurve(MakeCurve(Vec2(0, 0), Vec2(3, 0), Vec2(-1, 0), Vec2(1, 0)), 11);
  CheckCurve(MakeCurve(Vec2(0, 0), Vec2(0.01, 0.01), Vec2(0.02, 0.02), Vec2(5, 5)), 12);
  CheckCurve(MakeCurve(Vec2(1, 1), Vec2(-2, -2), Vec2(4, 4), Vec2(0, 0)), 13);
  // Exact queries on the line through it.
  const CubicBezier c = MakeCurve(Vec2(0, 0), Vec2(3, 0), Vec2(-1, 0), Vec2(1, 0));
  for (double s : { -2.0, -0.5, 0.0, 0.25, 1.0, 1.3, 1.9, 3.0 })
  {
    CheckAgainstDense(Vec2(s, 0.0), c);
  }
}

TEST(BezierCurves, CuspsAndLoops)
{
  // B'(1/2) = 0: a cusp.
  const CubicBezier cusp = MakeCurve(Vec2(0, 0), Vec2(1, 1), Vec2(0, 1), Vec2(1, 0));
  ASSERT_LT(cusp.Derivative(0.5).norm(), 1e-15);
  CheckCurve(cusp, 21, 40);
  CheckAgainstDense(cusp.Evaluate(0.5), cusp);
  CheckAgainstDense(cusp.Evaluate(0.5) + Vec2(0, 1e-3), cusp);
  CheckAgainstDense(cusp.Evaluate(0.5) - Vec2(0, 1e-3), cusp);
  // Self-intersecting loops, with queries at the crossing and inside.
  CheckCurve(MakeCurve(Vec2(0, 0), Vec2(3, 1), Vec2(-2, 1), Vec2(1, 0)), 22, 40);
  CheckCurve(MakeCurve(Vec2(0, 0), Vec2(2, 2), Vec2(-2, 2), Vec2(0, 0)), 23, 40); // closed
  CheckCurve(MakeCurve(Vec2(0, 0), Vec2(10, 1), Vec2(-9, 1), Vec2(1, 0)), 24, 40);
}

TEST(BezierCurves, TinyAndHugeScales)
{
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : { 1e-12, 1e-7, 1e5 })
  {
    for (double offset : { 0.0, 1.0, 1e6 })
    {
      for (int i = 0; i < 10; ++i)
      {
        const Vec2 o(offset, -0.5 * offset);
        CubicBezier c;
        for (Vec2& p : c.P)
        {
          p = o + scale * Vec2(u(rng), u(rng));
        }
        CheckCurve(c, 32 + i, 5, 4000);
      }
    }
  }
}

TEST(BezierCurves, CentreOfCurvatureOfAnArc)
{
  // A quarter circle of radius 1 seen from its centre: the distance varies by
  // only ~3e-4 along the whole curve, so every parameter is a near minimum.
  const double k = 0.5522847498;
  const CubicBezier arc = MakeCurve(Vec2(1, 0), Vec2(1, k), Vec2(k, 1), Vec2(0, 1));
  CheckAgainstDense(Vec2(0, 0), arc);
  for (double eps : { 1e-3, 1e-6, 1e-9 })
  {
    CheckAgainstDense(Vec2(eps, -eps), arc);
    CheckAgainstDense(Vec2(-eps, eps), arc);
  }
  // Symmetric curve, query on its axis: two equal minima, or one very flat
  // minimum at the vertex. (0, −0.09375) is the centre of curvature of the
  // vertex B(1/2) = (0, 0.75), where f(t) − f(1/2) is of order (t − 1/2)⁴.
  const CubicBezier bump = MakeCurve(Vec2(-1, 0), Vec2(-0.5, 1), Vec2(0.5, 1), Vec2(1, 0));
  for (double y : { -2.0, -0.09375, -0.09375 + 1e-9, 0.0, 0.5, 0.74, 0.76, 2.0 })
  {
    CheckAgainstDense(Vec2(0, y), bump);
  }
  EXPECT_NEAR(std::sqrt(ClosestPointOnCubicBezier(Vec2(0, -0.09375), bump).squaredDistance),
    0.84375, 1e-15);
  // Centres of curvature of random curves, from QueriesAround.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i)
  {
    const CubicBezier c =
      MakeCurve(Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)));
    CheckCurve(c, 100 + i, 3);
  }
}

TEST(BezierCurves, LowerBound)
{
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i)
  {
    const CubicBezier c =
      MakeCurve(Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)));
    const Vec2 x(3 * u(rng), 3 * u(rng));
    EXPECT_LE(gridfree::SquaredDistanceToCubicBezierLowerBound(x, c),
      ClosestPointOnCubicBezier(x, c).squaredDistance);
  }
}

//------------------------------------------------------------------------------
// Boundary geometry.

/// Random curve sets: chains of connected curves (sharing end points, like
/// diffusion curves) of various sizes, isolated curves, and a few degenerate
/// ones (points, lines with repeated control points, cusps).
std::vector<CubicBezier> MakeCurveSet(int n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<CubicBezier> curves;
  Vec2 last(u01(rng), u01(rng));
  while (static_cast<int>(curves.size()) < n)
  {
    const double kind = u01(rng);
    const double size = 0.01 + 0.15 * u01(rng) * u01(rng);
    auto near = [&](const Vec2& p) { return Vec2(p + size * Vec2(u01(rng) - 0.5, u01(rng) - 0.5)); };
    CubicBezier c;
    c.P[0] = kind < 0.7 ? last : Vec2(u01(rng), u01(rng)); // continue the chain
    if (kind > 0.97)
    {
      c.P[1] = c.P[2] = c.P[3] = c.P[0];
    }
    else if (kind > 0.94)
    {
      c.P[1] = c.P[0];
      c.P[3] = near(c.P[0]);
      c.P[2] = c.P[3];
    }
    else if (kind > 0.92)
    {
      c.P[3] = near(c.P[0]);
      c.P[1] = c.P[0] + (c.P[3] - c.P[0]) + Vec2(0, size);
      c.P[2] = c.P[0] + Vec2(0, size);
    }
    else
    {
      c.P[1] = near(c.P[0]);
      c.P[2] = near(c.P[1]);
      c.P[3] = near(c.P[2]);
    }
    last = c.P[3];
    curves.push_back(c);
  }
  return curves;
}

struct BruteForce
{
  double SquaredDistance = kInf;
  std::int64_t Curve = -1;
  std::vector<double> PerCurve;
};

BruteForce BruteForceClosest(const std::vector<CubicBezier>& curves, const Vec2& x)
{
  BruteForce b;
  for (std::size_t i = 0; i < curves.size(); ++i)
  {
    const double d2 = ClosestPointOnCubicBezier(x, curves[i]).squaredDistance;
    b.PerCurve.push_back(d2);
    if (d2 < b.SquaredDistance)
    {
      b.SquaredDistance = d2;
      b.Curve = static_cast<std::int64_t>(i);
    }
  }
  return b;
}

TEST(BezierBoundaryGeometry, MatchesBruteForce)
{
  for (std::uint64_t seed : { 1u, 2u, 3u })
  {
    const std::vector<CubicBezier> curves = MakeCurveSet(300, seed);
    const BezierBoundaryGeometry geometry(curves);
    ASSERT_EQ(geometry.NumberOfParts(), 300);
    ASSERT_EQ(geometry.Curves().size(), curves.size());
    const gridfree::BoundingBox<2> box = geometry.Bounds();
    const double diag = box.Diagonal();

    std::mt19937_64 rng(seed * 77);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<Vec2> queries;
    for (int i = 0; i < 300; ++i) // in and around the box, and far away
    {
      queries.push_back(
        box.Min + Vec2(u01(rng), u01(rng)).cwiseProduct(box.Extent()) * 1.4 - 0.2 * box.Extent());
    }
    for (int i = 0; i < 20; ++i)
    {
      queries.push_back(box.Center() + 50.0 * diag * Vec2(u01(rng) - 0.5, u01(rng) - 0.5));
    }
    for (int i = 0; i < 300; ++i) // on and very near the curves, at junctions
    {
      const CubicBezier& c = curves[rng() % curves.size()];
      const Vec2 b = c.Evaluate(i % 10 == 0 ? 0.0 : u01(rng));
      queries.push_back(b);
      queries.push_back(b + 1e-7 * Vec2(u01(rng) - 0.5, u01(rng) - 0.5));
      queries.push_back(b + 1e-3 * Vec2(u01(rng) - 0.5, u01(rng) - 0.5));
    }

    for (const Vec2& x : queries)
    {
      const BruteForce ref = BruteForceClosest(curves, x);
      const double dref = std::sqrt(ref.SquaredDistance);
      const double tol = 1e-12 * dref + 1e-15 * diag;
      const double d = geometry.Distance(x);
      EXPECT_NEAR(d, dref, tol) << x.transpose();

      const gridfree::ClosestPointResult<2> hit = geometry.ClosestPoint(x);
      ASSERT_GE(hit.primitive, 0);
      ASSERT_LT(hit.primitive, geometry.NumberOfParts());
      EXPECT_NEAR(hit.distance, dref, tol);
      EXPECT_EQ(hit.distance, d); // same traversal
      // Same curve as brute force, or a tie.
      if (hit.primitive != ref.Curve)
      {
        EXPECT_NEAR(std::sqrt(ref.PerCurve[hit.primitive]), dref, tol) << x.transpose();
      }
      const double t = hit.barycentric[1];
      ASSERT_TRUE(t >= 0.0 && t <= 1.0);
      EXPECT_DOUBLE_EQ(hit.barycentric[0] + hit.barycentric[1], 1.0);
      EXPECT_EQ(hit.point, curves[hit.primitive].Evaluate(t));
      EXPECT_NEAR((x - hit.point).norm(), hit.distance, 1e-14 * diag);

      const Vec2 n = geometry.Normal(hit);
      const Vec2 tangent = curves[hit.primitive].Derivative(t);
      if (tangent.norm() > 1e-6 * Size(curves[hit.primitive]))
      {
        EXPECT_NEAR(n.norm(), 1.0, 1e-14);
        EXPECT_NEAR(n.dot(tangent) / tangent.norm(), 0.0, 1e-14);
        EXPECT_GT(tangent[0] * n[1] - tangent[1] * n[0], 0.0); // left of the tangent
      }
      else if (Size(curves[hit.primitive]) > 0.0)
      {
        EXPECT_NEAR(n.norm(), 1.0, 1e-14);
      }
      if (HasFailure())
      {
        FAIL() << "seed " << seed << " query " << x.transpose();
      }
    }

    // The bounds hold the curves.
    for (const CubicBezier& c : curves)
    {
      for (int i = 0; i <= 200; ++i)
      {
        const Vec2 p = c.Evaluate(i / 200.0);
        EXPECT_TRUE((p.array() >= box.Min.array() - 1e-15).all() &&
          (p.array() <= box.Max.array() + 1e-15).all());
      }
    }
  }
}

TEST(BezierBoundaryGeometry, DistanceIsALowerBoundOfEveryCurve)
{
  // Walk on spheres needs an empty ball: no curve point may be closer than
  // Distance(x). Check against densely sampled points of every curve.
  const std::vector<CubicBezier> curves = MakeCurveSet(100, 9);
  const BezierBoundaryGeometry geometry(curves);
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (int q = 0; q < 200; ++q)
  {
    const Vec2 x(u(rng), u(rng));
    const double d = geometry.Distance(x);
    double sampled = kInf;
    for (const CubicBezier& c : curves)
    {
      for (int i = 0; i <= 500; ++i)
      {
        sampled = std::min(sampled, RelativePoint(c, x, i / 500.0).norm());
      }
    }
    EXPECT_LE(d, sampled * (1.0 + 1e-14)) << x.transpose();
    EXPECT_GT(d, sampled - 0.01) << x.transpose(); // sampling is dense enough
  }
}

TEST(BezierBoundaryGeometry, CircleOfFourArcs)
{
  // The standard 4-arc approximation of a circle deviates from it by at most
  // about 2.7e-4 of the radius; distances follow | |x − c| − r | within that.
  const double k = 0.5522847498;
  for (const auto& setup :
    { std::pair<Vec2, double>(Vec2(0, 0), 1.0), std::pair<Vec2, double>(Vec2(1e6, -2e6), 3.0),
      std::pair<Vec2, double>(Vec2(-0.5, 0.25), 1e-4) })
  {
    const Vec2 center = setup.first;
    const double r = setup.second;
    std::vector<CubicBezier> curves;
    const Vec2 e[4] = { Vec2(1, 0), Vec2(0, 1), Vec2(-1, 0), Vec2(0, -1) };
    for (int q = 0; q < 4; ++q)
    {
      const Vec2 a = e[q];
      const Vec2 b = e[(q + 1) % 4];
      curves.push_back(MakeCurve(
        center + r * a, center + r * (a + k * b), center + r * (b + k * a), center + r * b));
    }
    const BezierBoundaryGeometry geometry(curves);
    std::mt19937_64 rng(61);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    double worst = 0.0;
    std::vector<Vec2> queries = { center };
    for (int i = 0; i < 2000; ++i)
    {
      queries.push_back(center + r * Vec2(u(rng), u(rng)));
    }
    for (int i = 0; i < 500; ++i) // near the circle
    {
      const double phi = 3.2 * u(rng);
      queries.push_back(center + r * (1.0 + 1e-3 * u(rng)) * Vec2(std::cos(phi), std::sin(phi)));
    }
    for (const Vec2& x : queries)
    {
      const double exact = std::abs((x - center).norm() - r);
      const double d = geometry.Distance(x);
      EXPECT_NEAR(d, exact, 2.8e-4 * r) << x.transpose();
      worst = std::max(worst, std::abs(d - exact) / r);
      const auto hit = geometry.ClosestPoint(x);
      EXPECT_NEAR(std::abs((hit.point - center).norm() - r), 0.0, 2.8e-4 * r);
    }
    EXPECT_GT(worst, 2e-4); // the approximation error is really seen
  }
}

TEST(BezierBoundaryGeometry, NormalsOfDegenerateCurves)
{
  const Vec2 a(0, 0), b(1, 0), c(1, 1);
  // Repeated first control point: B'(0) = 0, the tangent is along P2 − P0.
  const CubicBezier start = MakeCurve(a, a, b, c);
  const Vec2 n0 = start.Normal(0.0);
  EXPECT_NEAR(n0.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n0.dot(b - a), 0.0, 1e-6);
  EXPECT_GT(n0[1], 0.0); // left of the direction of travel (+x)
  // Repeated last control point: the tangent at t = 1 is along P3 − P1.
  const CubicBezier end = MakeCurve(a, b, c, c);
  const Vec2 n1 = end.Normal(1.0);
  EXPECT_NEAR(n1.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n1.dot(c - b), 0.0, 1e-6);
  EXPECT_LT(n1[0], 0.0); // travelling +y, left is −x
  // Cusp: unit, and orthogonal to the tangent on one side of it.
  const CubicBezier cusp = MakeCurve(Vec2(0, 0), Vec2(1, 1), Vec2(0, 1), Vec2(1, 0));
  EXPECT_NEAR(cusp.Normal(0.5).norm(), 1.0, 1e-12);
  // A point curve has no normal.
  const CubicBezier point = MakeCurve(c, c, c, c);
  EXPECT_EQ(point.Normal(0.3), Vec2::Zero());

  const BezierBoundaryGeometry geometry({ start, point });
  gridfree::ClosestPointResult<2> hit = geometry.ClosestPoint(Vec2(-1, -0.5));
  EXPECT_EQ(hit.primitive, 0);
  EXPECT_EQ(hit.barycentric[1], 0.0);
  EXPECT_TRUE(geometry.Normal(hit).isApprox(n0));
  hit = geometry.ClosestPoint(Vec2(5, 5));
  EXPECT_TRUE(hit.primitive == 1 || hit.primitive == 0);
  hit.primitive = 1;
  EXPECT_EQ(geometry.Normal(hit), Vec2::Zero());
  hit.primitive = 7;
  EXPECT_EQ(geometry.Normal(hit), Vec2::Zero());
}

TEST(BezierBoundaryGeometry, EmptySingleAndInvalid)
{
  const BezierBoundaryGeometry empty({});
  EXPECT_EQ(empty.NumberOfParts(), 0);
  EXPECT_EQ(empty.Distance(Vec2(1, 2)), kInf);
  EXPECT_EQ(empty.ClosestPoint(Vec2(1, 2)).primitive, -1);
  EXPECT_EQ(empty.ClosestPoint(Vec2(1, 2)).distance, kInf);
  EXPECT_TRUE(empty.Bounds().IsEmpty());

  const CubicBezier c = MakeCurve(Vec2(0, 0), Vec2(1, 2), Vec2(3, -1), Vec2(4, 1));
  const BezierBoundaryGeometry single({ c });
  EXPECT_EQ(single.NumberOfParts(), 1);
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> u(-3.0, 6.0);
  for (int i = 0; i < 200; ++i)
  {
    const Vec2 x(u(rng), u(rng));
    const auto ref = ClosestPointOnCubicBezier(x, c);
    EXPECT_NEAR(single.Distance(x), std::sqrt(ref.squaredDistance), 1e-13);
    EXPECT_EQ(single.ClosestPoint(x).primitive, 0);
  }
  EXPECT_TRUE(single.Bounds().Contains(c.P[1]));

  const double nan = std::numeric_limits<double>::quiet_NaN();
  CubicBezier bad = c;
  bad.P[2] = Vec2(nan, 0);
  EXPECT_THROW(BezierBoundaryGeometry({ c, bad }), std::invalid_argument);
  bad.P[2] = Vec2(0, kInf);
  EXPECT_THROW(BezierBoundaryGeometry({ bad }), std::invalid_argument);
}

TEST(BezierBoundaryGeometry, ManyIdenticalCurves)
{
  // Coincident boxes and centres: the builder must fall back to median splits.
  const CubicBezier c = MakeCurve(Vec2(0, 0), Vec2(1, 2), Vec2(3, -1), Vec2(4, 1));
  const BezierBoundaryGeometry geometry(std::vector<CubicBezier>(1000, c));
  const Vec2 x(2, 3);
  EXPECT_NEAR(geometry.Distance(x), std::sqrt(ClosestPointOnCubicBezier(x, c).squaredDistance), 1e-14);
}
} // namespace

// Encloses: the parity of the +x ray's crossings with the curves' chords.
// A closed figure eight of two cubic loops encloses its two lobes and not
// the point where it crosses itself nor anything outside; an open curve's
// answer is its own business, but it must not fail.
TEST(BezierCurves, EnclosesByRayParity)
{
  // Two teardrops, each a closed cubic (P0 = P3) on either side of the
  // origin, around (±0.5, 0).
  CubicBezier right, left;
  right.P[0] = Vec2(0, 0);
  right.P[1] = Vec2(1.3, 1.0);
  right.P[2] = Vec2(1.3, -1.0);
  right.P[3] = Vec2(0, 0);
  left.P[0] = Vec2(0, 0);
  left.P[1] = Vec2(-1.3, -1.0);
  left.P[2] = Vec2(-1.3, 1.0);
  left.P[3] = Vec2(0, 0);
  const BezierBoundaryGeometry eight({ right, left });
  EXPECT_TRUE(eight.Encloses(Vec2(0.5, 0.05)));
  EXPECT_TRUE(eight.Encloses(Vec2(-0.5, -0.05)));
  EXPECT_FALSE(eight.Encloses(Vec2(0.0, 0.4)));
  EXPECT_FALSE(eight.Encloses(Vec2(1.5, 0.0)));
  EXPECT_FALSE(eight.Encloses(Vec2(-2.0, 0.1)));
  CubicBezier open;
  open.P[0] = Vec2(0, 0);
  open.P[1] = Vec2(1, 1);
  open.P[2] = Vec2(2, -1);
  open.P[3] = Vec2(3, 0);
  const BezierBoundaryGeometry curve({ open });
  EXPECT_NO_THROW(curve.Encloses(Vec2(1.0, 0.1)));
  EXPECT_FALSE(BezierBoundaryGeometry({}).Encloses(Vec2(0, 0)));
}
