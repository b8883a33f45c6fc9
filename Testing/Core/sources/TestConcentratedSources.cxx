// Tests of the ball query tree and of point and curve source sampling.
//
// Tree and point queries must equal brute force exactly (same per-item
// tests, only the pruning differs). Curve clipping is checked against closed
// forms, and curve sampling against the properties the estimator relies on:
// samples inside the ball and on the curve, uniform in arc length, linearly
// interpolated strengths and an unbiased estimate of the integral over the
// clipped curve. Seeds are fixed, so failures are reproducible.
#include <gridfree/sources/ConcentratedSources.h>
#include <gridfree/geometry/BallQueryTree.h>
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/math/Vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace
{
using gridfree::BallQueryTree;
using gridfree::BoundingBox;
using gridfree::CurveSources;
using gridfree::PointSources;
using gridfree::RandomStream;
using gridfree::Vec;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
using Segment = std::array<std::int64_t, 2>;

template <int DIM>
Vec<DIM> RandomVec(std::mt19937_64& gen, double lo, double hi)
{
  std::uniform_real_distribution<double> u(lo, hi);
  Vec<DIM> v;
  for (int i = 0; i < DIM; ++i)
  {
    v[i] = u(gen);
  }
  return v;
}

/// Embeds planar coordinates; the third one (3D) is a constant offset so the
/// 3D cases are not confined to z = 0.
template <int DIM>
Vec<DIM> Planar(double px, double py, double pz = 0.25)
{
  Vec<DIM> v;
  v[0] = px;
  v[1] = py;
  if constexpr (DIM == 3)
  {
    v[2] = pz;
  }
  return v;
}

/// Kolmogorov-Smirnov statistic of samples against the uniform law on [0, 1].
double KsStatistic(std::vector<double> u)
{
  std::sort(u.begin(), u.end());
  const double n = static_cast<double>(u.size());
  double d = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i)
  {
    d = std::max({ d, std::abs(u[i] - double(i) / n), std::abs(u[i] - double(i + 1) / n) });
  }
  return d;
}

/// 99.9% critical value of the KS statistic.
double KsThreshold(std::size_t n)
{
  return 1.95 / std::sqrt(static_cast<double>(n));
}

template <int DIM>
std::vector<std::size_t> TreeQuery(const BallQueryTree<DIM>& tree, const Vec<DIM>& c, double r)
{
  std::vector<std::size_t> hits;
  tree.ForEachOverlappingBall(c, r, [&](std::size_t i) { hits.push_back(i); });
  std::sort(hits.begin(), hits.end());
  return hits;
}

template <int DIM>
std::vector<std::size_t> BruteBoxQuery(
  const std::vector<Vec<DIM>>& lo, const std::vector<Vec<DIM>>& hi, const Vec<DIM>& c, double r)
{
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < lo.size(); ++i)
  {
    if (BoundingBox<DIM>(lo[i], hi[i]).SquaredDistance(c) <= r * r)
    {
      hits.push_back(i);
    }
  }
  return hits;
}

//------------------------------------------------------------------------------
// BallQueryTree
//------------------------------------------------------------------------------
template <int DIM>
void CheckTreeAgainstBruteForce(std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::size_t n = 3000;
  std::vector<Vec<DIM>> lo, hi;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Vec<DIM> p = RandomVec<DIM>(gen, -1.0, 1.0);
    if (i % 3 == 0)
    {
      lo.push_back(p); // a point
      hi.push_back(p);
    }
    else if (i % 7 == 0 && i > 0)
    {
      lo.push_back(lo[i / 2]); // a duplicate
      hi.push_back(hi[i / 2]);
    }
    else
    {
      const Vec<DIM> e = RandomVec<DIM>(gen, 0.0, 0.1);
      lo.push_back(p);
      hi.push_back(p + e);
    }
  }
  const BallQueryTree<DIM> tree(lo, hi);
  ASSERT_EQ(tree.Size(), n);

  int withHits = 0, withoutHits = 0;
  for (int q = 0; q < 1500; ++q)
  {
    Vec<DIM> c = RandomVec<DIM>(gen, -1.5, 1.5);
    double r = 0.3 * std::pow(unit(gen), 3.0);
    if (q % 10 == 0)
    {
      r = 0.0;
    }
    if (q % 20 == 0)
    {
      c = lo[q % n]; // radius 0 on a box corner: touching counts
    }
    if (q % 30 == 1)
    {
      c = Vec<DIM>::Constant(5.0); // far away
    }
    const auto hits = TreeQuery<DIM>(tree, c, r);
    ASSERT_EQ(hits, (BruteBoxQuery<DIM>(lo, hi, c, r))) << "query " << q;
    ASSERT_TRUE(std::adjacent_find(hits.begin(), hits.end()) == hits.end());
    (hits.empty() ? withoutHits : withHits) += 1;
  }
  // Both outcomes must be exercised, or the comparison proves little.
  EXPECT_GT(withHits, 300);
  EXPECT_GT(withoutHits, 100);
}

TEST(BallQueryTree, MatchesBruteForce2D)
{
  CheckTreeAgainstBruteForce<2>(1);
}

TEST(BallQueryTree, MatchesBruteForce3D)
{
  CheckTreeAgainstBruteForce<3>(2);
}

TEST(BallQueryTree, EmptyAndDegenerateInputs)
{
  using V = Vec<3>;
  BallQueryTree<3> empty;
  EXPECT_TRUE(empty.Empty());
  EXPECT_TRUE(empty.Bounds().IsEmpty());
  EXPECT_TRUE(TreeQuery<3>(empty, V::Zero(), kInf).empty());
  empty.Build({}, {});
  EXPECT_TRUE(TreeQuery<3>(empty, V::Zero(), kInf).empty());

  // All items at one point: median splits must still terminate and balance.
  const std::vector<V> same(1000, V(0.5, -0.25, 2.0));
  const BallQueryTree<3> tree(same, same);
  EXPECT_EQ(TreeQuery<3>(tree, V(0.5, -0.25, 2.0), 0.0).size(), 1000u);
  EXPECT_EQ(TreeQuery<3>(tree, V(0.5, -0.25, 2.1), 0.05).size(), 0u);
  EXPECT_EQ(TreeQuery<3>(tree, V::Zero(), kInf).size(), 1000u);
  EXPECT_TRUE(TreeQuery<3>(tree, V(0.5, -0.25, 2.0), -1.0).empty());
  EXPECT_TRUE(TreeQuery<3>(tree, V(0.5, -0.25, 2.0), std::nan("")).empty());
  EXPECT_EQ(tree.Bounds().Min, same[0]);
  EXPECT_EQ(tree.Bounds().Max, same[0]);

  // A rebuild replaces the content.
  BallQueryTree<3> one(same, same);
  one.Build({ V(1, 1, 1) }, { V(2, 2, 2) });
  EXPECT_EQ(TreeQuery<3>(one, V(0, 0, 0), 2.0), (std::vector<std::size_t>{ 0 }));
  EXPECT_TRUE(TreeQuery<3>(one, V(0, 0, 0), 1.7).empty()); // sqrt(3) = 1.732

  BallQueryTree<2> bad;
  using W = Vec<2>;
  EXPECT_THROW(bad.Build({ W(0, 0) }, {}), std::invalid_argument);
  EXPECT_THROW(bad.Build({ W(1, 0) }, { W(0, 0) }), std::invalid_argument);
  EXPECT_THROW(bad.Build({ W(std::nan(""), 0) }, { W(0, 0) }), std::invalid_argument);
  EXPECT_THROW(bad.Build({ W(0, 0) }, { W(kInf, 0) }), std::invalid_argument);
}

TEST(BallQueryTree, ConcurrentQueriesAgree)
{
  std::mt19937_64 gen(3);
  std::vector<Vec<2>> pts(2000);
  for (auto& p : pts)
  {
    p = RandomVec<2>(gen, 0.0, 1.0);
  }
  const BallQueryTree<2> tree(pts, pts);
  std::vector<Vec<2>> centers(400);
  for (auto& c : centers)
  {
    c = RandomVec<2>(gen, 0.0, 1.0);
  }
  std::vector<std::vector<std::size_t>> expected;
  for (const auto& c : centers)
  {
    expected.push_back(TreeQuery<2>(tree, c, 0.05));
  }
  std::vector<int> mismatches(2, 0);
  auto work = [&](int id) {
    for (int pass = 0; pass < 5; ++pass)
    {
      for (std::size_t q = 0; q < centers.size(); ++q)
      {
        mismatches[id] += TreeQuery<2>(tree, centers[q], 0.05) != expected[q];
      }
    }
  };
  std::thread a(work, 0), b(work, 1);
  a.join();
  b.join();
  EXPECT_EQ(mismatches[0] + mismatches[1], 0);
}

//------------------------------------------------------------------------------
// PointSources
//------------------------------------------------------------------------------
template <int DIM>
void CheckPointSourcesAgainstBruteForce(std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::size_t n = 4000;
  std::vector<Vec<DIM>> pos(n);
  std::vector<double> str(2 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    pos[i] = (i % 11 == 5) ? pos[i - 1] : RandomVec<DIM>(gen, -1.0, 1.0);
    str[2 * i] = static_cast<double>(i); // identifies the source
    str[2 * i + 1] = -0.5 * static_cast<double>(i);
  }
  PointSources<DIM> src;
  src.Set(pos, 2, str);
  ASSERT_EQ(src.Size(), n);
  ASSERT_EQ(src.Components(), 2);

  int withHits = 0;
  for (int q = 0; q < 1500; ++q)
  {
    Vec<DIM> x = RandomVec<DIM>(gen, -1.2, 1.2);
    double r = 0.25 * std::pow(unit(gen), 2.0);
    if (q % 10 == 0)
    {
      x = pos[(q * 7) % n];
      r = (q % 20 == 0) ? 0.0 : r; // a source at the center with radius 0: excluded
    }
    std::vector<std::size_t> hits;
    src.ForEachInBall(x, r, [&](const Vec<DIM>& z, const double* s) {
      const auto i = static_cast<std::size_t>(s[0]);
      ASSERT_LT(i, n);
      ASSERT_EQ(z, pos[i]);
      ASSERT_EQ(s[1], -0.5 * s[0]);
      hits.push_back(i);
    });
    std::sort(hits.begin(), hits.end());
    std::vector<std::size_t> brute;
    for (std::size_t i = 0; i < n; ++i)
    {
      if ((pos[i] - x).squaredNorm() < r * r)
      {
        brute.push_back(i);
      }
    }
    ASSERT_EQ(hits, brute) << "query " << q;
    withHits += !hits.empty();
    if (r == 0.0)
    {
      ASSERT_TRUE(hits.empty());
    }
  }
  EXPECT_GT(withHits, 300);
  EXPECT_LT(withHits, 1400);
}

TEST(PointSources, MatchesBruteForce2D)
{
  CheckPointSourcesAgainstBruteForce<2>(4);
}

TEST(PointSources, MatchesBruteForce3D)
{
  CheckPointSourcesAgainstBruteForce<3>(5);
}

TEST(PointSources, StrictBoundaryEmptySetAndValidation)
{
  using V = Vec<2>;
  PointSources<2> src;
  EXPECT_TRUE(src.Empty());
  EXPECT_EQ(src.BoundsMin(), V::Zero());
  EXPECT_EQ(src.BoundsMax(), V::Zero());
  int calls = 0;
  src.ForEachInBall(V::Zero(), kInf, [&](const V&, const double*) { ++calls; });
  EXPECT_EQ(calls, 0);

  src.Set({ V(1, 0), V(0, 3), V(-2, 0.5) }, 1, { 10, 20, 30 });
  EXPECT_EQ(src.BoundsMin(), V(-2, 0));
  EXPECT_EQ(src.BoundsMax(), V(1, 3));
  double sum = 0.0;
  auto add = [&](const V&, const double* s) { sum += s[0]; };
  src.ForEachInBall(V::Zero(), 1.0, add); // (1, 0) lies on the sphere
  EXPECT_EQ(sum, 0.0);
  src.ForEachInBall(V::Zero(), std::nextafter(1.0, 2.0), add);
  EXPECT_EQ(sum, 10.0);
  src.ForEachInBall(V::Zero(), kInf, add);
  EXPECT_EQ(sum, 70.0);

  EXPECT_THROW(src.Set({ V(0, 0) }, 2, { 1.0 }), std::invalid_argument);
  EXPECT_THROW(src.Set({ V(0, 0) }, 0, {}), std::invalid_argument);
  EXPECT_THROW(src.Set({ V(std::nan(""), 0) }, 1, { 1.0 }), std::invalid_argument);
  EXPECT_THROW(src.Set({ V(0, 0) }, 1, { kInf }), std::invalid_argument);
  EXPECT_EQ(src.Size(), 3u); // a failed Set keeps the old content
}

//------------------------------------------------------------------------------
// CurveSources: clipping
//------------------------------------------------------------------------------
/// A unit vector orthogonal to u (|u| = 1).
template <int DIM>
Vec<DIM> Orthogonal(const Vec<DIM>& u, std::mt19937_64& gen)
{
  Vec<DIM> v = RandomVec<DIM>(gen, -1.0, 1.0);
  v -= v.dot(u) * u;
  return v.normalized();
}

template <int DIM>
void CheckStraightLineChords(std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  typename CurveSources<DIM>::Scratch scratch;
  for (int q = 0; q < 500; ++q)
  {
    const Vec<DIM> x = RandomVec<DIM>(gen, -2.0, 2.0);
    const double r = 0.1 + unit(gen);
    const double h = 1.2 * r * unit(gen); // some lines miss the ball
    const Vec<DIM> u = RandomVec<DIM>(gen, -1.0, 1.0).normalized();
    const Vec<DIM> foot = x + h * Orthogonal<DIM>(u, gen);
    CurveSources<DIM> line;
    line.Set({ foot - 7.0 * u, foot + 5.0 * u }, { Segment{ 0, 1 } }, 1, { 0.0, 0.0 });
    const double expected = h < r ? 2.0 * std::sqrt(r * r - h * h) : 0.0;
    ASSERT_NEAR(line.LengthInBall(x, r, scratch), expected, 1e-12) << "query " << q;
  }
}

TEST(CurveSources, StraightLineChord2D)
{
  CheckStraightLineChords<2>(6);
}

TEST(CurveSources, StraightLineChord3D)
{
  CheckStraightLineChords<3>(7);
}

template <int DIM>
void CheckSpecialSegments()
{
  using V = Vec<DIM>;
  typename CurveSources<DIM>::Scratch scratch;
  const V x = Planar<DIM>(0.0, 0.0, 0.0);
  RandomStream rng(11, 0);
  V z = V::Constant(-7.0);
  double s = -7.0, inverseDensity = -7.0;

  // Tangent line: touches the sphere at one point, measure zero.
  CurveSources<DIM> tangent;
  tangent.Set({ Planar<DIM>(-5, 1, 0), Planar<DIM>(5, 1, 0) }, { Segment{ 0, 1 } }, 1, { 1, 1 });
  EXPECT_EQ(tangent.LengthInBall(x, 1.0, scratch), 0.0);
  EXPECT_FALSE(tangent.SampleInBall(x, 1.0, rng, scratch, z, &s, inverseDensity));
  EXPECT_EQ(inverseDensity, 0.0);
  EXPECT_EQ(z, V::Constant(-7.0)); // untouched
  EXPECT_EQ(s, -7.0);
  EXPECT_GT(tangent.LengthInBall(x, std::nextafter(1.0, 2.0), scratch), 0.0);

  // Segment on a line through the ball that stops before reaching it.
  CurveSources<DIM> shortOne;
  shortOne.Set({ Planar<DIM>(-5, 0, 0), Planar<DIM>(-1.5, 0, 0) }, { Segment{ 0, 1 } }, 1, { 1, 1 });
  EXPECT_EQ(shortOne.LengthInBall(x, 1.0, scratch), 0.0);
  EXPECT_FALSE(shortOne.SampleInBall(x, 1.0, rng, scratch, z, &s, inverseDensity));

  // Segment ending inside: from the sphere to its end.
  CurveSources<DIM> ending;
  ending.Set({ Planar<DIM>(-5, 0.6, 0), Planar<DIM>(0.3, 0.6, 0) }, { Segment{ 0, 1 } }, 1, { 1, 1 });
  EXPECT_NEAR(ending.LengthInBall(x, 1.0, scratch), 0.8 + 0.3, 1e-14);

  // Polyline fully inside: all of it, exactly.
  CurveSources<DIM> inside;
  inside.Set({ Planar<DIM>(-0.3, 0.1, 0.1), Planar<DIM>(0.2, 0.4, -0.2), Planar<DIM>(0.5, -0.1, 0) },
    { Segment{ 0, 1 }, Segment{ 1, 2 } }, 1, { 0, 0, 0 });
  EXPECT_DOUBLE_EQ(inside.LengthInBall(x, 1.0, scratch), inside.TotalLength());

  // Radius zero and negative radius: nothing.
  EXPECT_EQ(inside.LengthInBall(Planar<DIM>(0.2, 0.4, -0.2), 0.0, scratch), 0.0);
  EXPECT_EQ(inside.LengthInBall(x, -1.0, scratch), 0.0);
}

TEST(CurveSources, TangentOutsideInside2D)
{
  CheckSpecialSegments<2>();
}

TEST(CurveSources, TangentOutsideInside3D)
{
  CheckSpecialSegments<3>();
}

/// Regular M-gon inscribed in the circle of radius rho around the origin (in
/// the plane z = 0 in 3D), as a closed polyline.
template <int DIM>
CurveSources<DIM> Polygon(int m, double rho)
{
  std::vector<Vec<DIM>> v;
  std::vector<Segment> seg;
  for (int i = 0; i < m; ++i)
  {
    const double a = 2.0 * kPi * i / m;
    v.push_back(Planar<DIM>(rho * std::cos(a), rho * std::sin(a), 0.0));
    seg.push_back({ i, (i + 1) % m });
  }
  CurveSources<DIM> c;
  c.Set(v, seg, 1, std::vector<double>(v.size(), 1.0));
  return c;
}

template <int DIM>
void CheckPolygonCircle()
{
  const int m = 4096;
  const double rho = 1.5;
  const CurveSources<DIM> poly = Polygon<DIM>(m, rho);
  typename CurveSources<DIM>::Scratch scratch;
  EXPECT_EQ(poly.NumberOfSegments(), static_cast<std::size_t>(m));
  const double perimeter = 2.0 * m * rho * std::sin(kPi / m);
  EXPECT_NEAR(poly.TotalLength(), perimeter, 1e-12 * perimeter);
  EXPECT_NEAR(poly.LengthInBall(Planar<DIM>(0, 0, 0), 2.0, scratch), perimeter, 1e-12 * perimeter);
  EXPECT_EQ(poly.LengthInBall(Planar<DIM>(0, 0, 0), 1.4, scratch), 0.0); // inside the hole

  // A ball centered at distance e from the circle's point (rho, 0) along the
  // normal of its plane (3D) or radially outward (2D). On the circle, at angle
  // theta, |p - c|^2 = rho^2 + (rho + e)^2 - 2 rho (rho + e) cos(theta) in 2D,
  // 2 rho^2 (1 - cos(theta)) + e^2 in 3D. The part inside is the arc
  // |theta| < theta_max; the polygon differs from the arc by O(1 / m^2).
  const double e = 0.2, r = 0.7;
  double cosMax;
  Vec<DIM> c;
  if constexpr (DIM == 2)
  {
    c = Planar<DIM>(rho + e, 0.0);
    cosMax = (rho * rho + (rho + e) * (rho + e) - r * r) / (2.0 * rho * (rho + e));
  }
  else
  {
    c = Planar<DIM>(rho, 0.0, e);
    cosMax = 1.0 - (r * r - e * e) / (2.0 * rho * rho);
  }
  const double arc = 2.0 * rho * std::acos(cosMax);
  EXPECT_NEAR(poly.LengthInBall(c, r, scratch), arc, 1e-5 * arc);
  EXPECT_GT(scratch.Pieces.size(), 100u); // many segments really were clipped
}

TEST(CurveSources, PolygonCircleArc2D)
{
  CheckPolygonCircle<2>();
}

TEST(CurveSources, PolygonCircleArc3D)
{
  CheckPolygonCircle<3>();
}

TEST(CurveSources, SetValidatesAndDropsZeroLengthSegments)
{
  using V = Vec<3>;
  CurveSources<3> c;
  EXPECT_TRUE(c.Empty());
  EXPECT_EQ(c.BoundsMin(), V::Zero());
  typename CurveSources<3>::Scratch scratch;
  EXPECT_EQ(c.LengthInBall(V::Zero(), kInf, scratch), 0.0);

  const std::vector<V> v = { V(0, 0, 0), V(3, 0, 0), V(3, 4, 0), V(3, 0, 0) };
  c.Set(v, { Segment{ 0, 1 }, Segment{ 1, 3 }, Segment{ 1, 2 }, Segment{ 2, 2 } }, 2,
    { 0, 0, 1, 1, 2, 2, 3, 3 });
  EXPECT_EQ(c.NumberOfSegments(), 2u); // (1, 3) and (2, 2) have zero length
  EXPECT_EQ(c.Components(), 2);
  EXPECT_DOUBLE_EQ(c.TotalLength(), 7.0);
  EXPECT_EQ(c.BoundsMin(), V(0, 0, 0));
  EXPECT_EQ(c.BoundsMax(), V(3, 4, 0));

  EXPECT_THROW(c.Set(v, { Segment{ 0, 4 } }, 1, { 0, 0, 0, 0 }), std::invalid_argument);
  EXPECT_THROW(c.Set(v, { Segment{ -1, 0 } }, 1, { 0, 0, 0, 0 }), std::invalid_argument);
  EXPECT_THROW(c.Set(v, { Segment{ 0, 1 } }, 1, { 0, 0, 0 }), std::invalid_argument);
  EXPECT_THROW(c.Set(v, { Segment{ 0, 1 } }, 0, {}), std::invalid_argument);
  EXPECT_THROW(c.Set(v, { Segment{ 0, 1 } }, 1, { 0, std::nan(""), 0, 0 }), std::invalid_argument);
  EXPECT_THROW(c.Set({ V(0, 0, 0), V(0, kInf, 0) }, { Segment{ 0, 1 } }, 1, { 0, 0 }),
    std::invalid_argument);
  EXPECT_EQ(c.NumberOfSegments(), 2u); // a failed Set keeps the old content

  c.Set({ V(1, 1, 1) }, { Segment{ 0, 0 } }, 1, { 5 });
  EXPECT_TRUE(c.Empty());
  EXPECT_EQ(c.TotalLength(), 0.0);
}

//------------------------------------------------------------------------------
// CurveSources: sampling
//------------------------------------------------------------------------------
/// A zigzag polyline with random vertices in [-1, 1]^DIM.
template <int DIM>
void RandomPolyline(std::mt19937_64& gen, int n, std::vector<Vec<DIM>>& v, std::vector<Segment>& s)
{
  v.clear();
  s.clear();
  for (int i = 0; i < n; ++i)
  {
    v.push_back(RandomVec<DIM>(gen, -1.0, 1.0));
    if (i > 0)
    {
      s.push_back({ i - 1, i });
    }
  }
}

template <int DIM>
void CheckSamplesInsideAndOnCurve(std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<DIM>> v;
  std::vector<Segment> s;
  RandomPolyline<DIM>(gen, 300, v, s);
  CurveSources<DIM> curve;
  curve.Set(v, s, 1, std::vector<double>(v.size(), 1.0));
  typename CurveSources<DIM>::Scratch scratch;
  RandomStream rng(seed, 0);
  int sampled = 0;
  for (int q = 0; q < 2000; ++q)
  {
    const Vec<DIM> x = RandomVec<DIM>(gen, -1.2, 1.2);
    const double r = 0.3 * unit(gen);
    Vec<DIM> z = Vec<DIM>::Zero();
    double strength, inverseDensity;
    const double expected = curve.LengthInBall(x, r, scratch);
    const bool ok = curve.SampleInBall(x, r, rng, scratch, z, &strength, inverseDensity);
    ASSERT_EQ(ok, expected > 0.0);
    if (!ok)
    {
      continue;
    }
    ASSERT_GT(inverseDensity, 0.0);
    ASSERT_TRUE(std::isfinite(inverseDensity));
    ++sampled;
    ASSERT_LE((z - x).norm(), r * (1.0 + 1e-12));
    double d2 = kInf;
    for (const auto& seg : s)
    {
      d2 = std::min(d2, gridfree::SquaredDistanceToSegment<DIM>(z, v[seg[0]], v[seg[1]]));
    }
    ASSERT_LE(std::sqrt(d2), 1e-14);
    ASSERT_NEAR(strength, 1.0, 1e-14);
  }
  EXPECT_GT(sampled, 500);
}

TEST(CurveSources, SamplesInsideBallAndOnCurve2D)
{
  CheckSamplesInsideAndOnCurve<2>(8);
}

TEST(CurveSources, SamplesInsideBallAndOnCurve3D)
{
  CheckSamplesInsideAndOnCurve<3>(9);
}

/// The line y = 0.6 crosses the unit ball around the origin on x in
/// [-0.8, 0.8]; a vertex at x = 0.4 splits that chord into pieces. Points
/// must have density ∝ 1/r = 1/√(x² + 0.36) along the whole chord, so the
/// pieces are weighted by their ∫ dl/r, and 1/p(z) = r ∫ dl/r.
template <int DIM>
void CheckInverseDistanceAlongChord()
{
  CurveSources<DIM> line;
  line.Set({ Planar<DIM>(-3.0, 0.6), Planar<DIM>(0.4, 0.6), Planar<DIM>(3.0, 0.6) },
    { Segment{ 0, 1 }, Segment{ 1, 2 } }, 1, { 0, 0, 0 });
  const Vec<DIM> x = Planar<DIM>(0.0, 0.0);
  const double total = 2.0 * std::asinh(0.8 / 0.6);
  // The chord's CDF, to map samples to [0, 1].
  auto cdf = [&](double l) { return (std::asinh(l / 0.6) + std::asinh(0.8 / 0.6)) / total; };
  typename CurveSources<DIM>::Scratch scratch;
  RandomStream rng(12, DIM);
  const std::size_t n = 20000;
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    Vec<DIM> z = Vec<DIM>::Zero();
    double s, inverseDensity;
    ASSERT_TRUE(line.SampleInBall(x, 1.0, rng, scratch, z, &s, inverseDensity));
    ASSERT_NEAR(inverseDensity, total * (z - x).norm(), 1e-12);
    f[i] = cdf(z[0]);
  }
  EXPECT_LT(KsStatistic(f), KsThreshold(n));

  // The same check must reject plausible mistakes. (a) Points uniform along
  // the chord (the density before it was ∝ 1/r):
  RandomStream bad(13, DIM);
  std::vector<double> g(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    g[i] = cdf(-0.8 + 1.6 * bad.NextDouble());
  }
  EXPECT_GT(KsStatistic(g), KsThreshold(n));
  // (b) The right density within each piece, the pieces picked with equal odds:
  const double split = cdf(0.4);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double u = bad.NextDouble();
    g[i] = bad.NextDouble() < 0.5 ? split * u : split + (1.0 - split) * u;
  }
  EXPECT_GT(KsStatistic(g), KsThreshold(n));
  // (c) A density off by only 10%: 1 + 0.1 cos(pi f), by inverting its CDF.
  for (std::size_t i = 0; i < n; ++i)
  {
    const double u = bad.NextDouble();
    double t = u;
    for (int it = 0; it < 50; ++it)
    {
      t -= (t + 0.1 * std::sin(kPi * t) / kPi - u) / (1.0 + 0.1 * std::cos(kPi * t));
    }
    g[i] = t;
  }
  EXPECT_GT(KsStatistic(g), KsThreshold(n));
}

TEST(CurveSources, InverseDistanceAlongClippedChord2D)
{
  CheckInverseDistanceAlongChord<2>();
}

TEST(CurveSources, InverseDistanceAlongClippedChord3D)
{
  CheckInverseDistanceAlongChord<3>();
}

/// In 3D a sample of the free-space ∫ dl/(4π r) is the same number whatever
/// the point drawn, however close the walk passes: p ∝ 1/r cancels the pole.
/// Drawn uniformly, a point 10⁻⁴ from a unit segment gives samples spread
/// over four orders of magnitude.
TEST(CurveSources, InverseDistanceCancelsThePoleIn3D)
{
  using V = Vec<3>;
  CurveSources<3> seg;
  seg.Set({ V(-0.5, 0.0, 0.0), V(0.3, 0.0, 0.0), V(0.5, 0.0, 0.0) },
    { Segment{ 0, 1 }, Segment{ 1, 2 } }, 1, { 1.0, 1.0, 1.0 });
  typename CurveSources<3>::Scratch scratch;
  RandomStream rng(17, 0);
  for (const double h : { 1e-4, 0.01, 0.3 })
  {
    const V x(0.1, h, 0.0);
    // ∫ dl/r over x ∈ [−0.5, 0.5] seen from (0.1, h): asinh(0.4/h) + asinh(0.6/h).
    const double exact = (std::asinh(0.4 / h) + std::asinh(0.6 / h)) / (4.0 * kPi);
    for (int i = 0; i < 200; ++i)
    {
      V z = V::Zero();
      double s, inverseDensity;
      ASSERT_TRUE(seg.SampleInBall(x, 2.0, rng, scratch, z, &s, inverseDensity));
      ASSERT_NEAR(inverseDensity / (4.0 * kPi * (z - x).norm()), exact, 1e-12 * exact) << h;
    }
  }
}

TEST(CurveSources, StrengthIsLinearAlongSegment)
{
  using V = Vec<3>;
  const V a(-1.0, 0.3, 0.2), b(2.0, -0.5, 0.9);
  CurveSources<3> seg;
  seg.Set({ a, b }, { Segment{ 0, 1 } }, 2, { 0.0, 5.0, 1.0, -3.0 });
  typename CurveSources<3>::Scratch scratch;
  RandomStream rng(14, 0);
  const V x(0.5, 0.0, 0.5);
  double lo = 1.0, hi = 0.0;
  for (int i = 0; i < 2000; ++i)
  {
    V z = V::Zero();
    double s[2], inverseDensity;
    ASSERT_TRUE(seg.SampleInBall(x, 1.0, rng, scratch, z, s, inverseDensity));
    const double fraction = (z - a).norm() / (b - a).norm();
    ASSERT_NEAR(s[0], fraction, 1e-12);
    ASSERT_NEAR(s[1], 5.0 - 8.0 * fraction, 1e-12);
    lo = std::min(lo, fraction);
    hi = std::max(hi, fraction);
  }
  // The ball covers an interior part of the segment, not all of it.
  EXPECT_GT(lo, 0.05);
  EXPECT_LT(hi, 0.95);
  EXPECT_GT(hi - lo, 0.3);
}

/// E[s(z) k(z)/p(z)] = integral over gamma inside B of s k, for a smooth k. The
/// reference is a midpoint rule over every full segment with the indicator of
/// the open ball, which does not share any code with the clipping.
template <int DIM>
void CheckImportanceSamplingIdentity()
{
  // A spiral (helix in 3D) of 400 segments crossing the ball several times.
  std::vector<Vec<DIM>> v;
  std::vector<Segment> seg;
  std::vector<double> str;
  const int m = 400;
  for (int i = 0; i <= m; ++i)
  {
    const double a = 6.0 * kPi * i / m;
    const double rad = 0.3 + 0.6 * i / m;
    v.push_back(Planar<DIM>(rad * std::cos(a), rad * std::sin(a), -0.5 + double(i) / m));
    str.push_back(1.0 + v.back()[0]);              // component 0
    str.push_back(std::cos(3.0 * v.back()[1]));    // component 1
    if (i > 0)
    {
      seg.push_back({ i - 1, i });
    }
  }
  CurveSources<DIM> curve;
  curve.Set(v, seg, 2, str);
  const Vec<DIM> x = Planar<DIM>(0.35, 0.1, 0.05);
  const double r = 0.6;
  auto kernel = [&](const Vec<DIM>& z) { return 1.0 / (1.0 + (z - x).squaredNorm()); };

  double reference[2] = { 0.0, 0.0 };
  const int sub = 2000;
  for (const auto& s : seg)
  {
    const Vec<DIM> a = v[s[0]], d = v[s[1]] - v[s[0]];
    const double h = d.norm() / sub;
    for (int j = 0; j < sub; ++j)
    {
      const double t = (j + 0.5) / sub;
      const Vec<DIM> p = a + t * d;
      if ((p - x).squaredNorm() < r * r)
      {
        for (int c = 0; c < 2; ++c)
        {
          const double sv = (1.0 - t) * str[2 * s[0] + c] + t * str[2 * s[1] + c];
          reference[c] += h * sv * kernel(p);
        }
      }
    }
  }

  typename CurveSources<DIM>::Scratch scratch;
  RandomStream rng(15, DIM);
  const int n = 20000;
  double sum[2] = { 0, 0 }, sum2[2] = { 0, 0 };
  for (int i = 0; i < n; ++i)
  {
    Vec<DIM> z = Vec<DIM>::Zero();
    double s[2], inverseDensity;
    ASSERT_TRUE(curve.SampleInBall(x, r, rng, scratch, z, s, inverseDensity));
    for (int c = 0; c < 2; ++c)
    {
      const double y = inverseDensity * s[c] * kernel(z);
      sum[c] += y;
      sum2[c] += y * y;
    }
  }
  EXPECT_GT(scratch.Pieces.size(), 2u); // the spiral crosses the ball repeatedly
  for (int c = 0; c < 2; ++c)
  {
    const double mean = sum[c] / n;
    const double stderror = std::sqrt((sum2[c] / n - mean * mean) / (n - 1));
    EXPECT_GT(stderror, 0.0);
    EXPECT_GT(std::abs(reference[c]), 20.0 * stderror); // the check is not vacuous
    EXPECT_NEAR(mean, reference[c], 5.0 * stderror) << "component " << c;
  }
}

TEST(CurveSources, ImportanceSamplingIdentity2D)
{
  CheckImportanceSamplingIdentity<2>();
}

TEST(CurveSources, ImportanceSamplingIdentity3D)
{
  CheckImportanceSamplingIdentity<3>();
}

TEST(CurveSources, ScratchStopsGrowing)
{
  std::mt19937_64 gen(16);
  std::vector<Vec<2>> v;
  std::vector<Segment> s;
  RandomPolyline<2>(gen, 500, v, s);
  CurveSources<2> curve;
  curve.Set(v, s, 1, std::vector<double>(v.size(), 0.0));
  typename CurveSources<2>::Scratch scratch;
  RandomStream rng(16, 0);
  Vec<2> z = Vec<2>::Zero();
  double strength, inverseDensity;
  // The largest ball first: later queries have fewer hits and must reuse it.
  ASSERT_TRUE(curve.SampleInBall(Vec<2>::Zero(), 0.5, rng, scratch, z, &strength, inverseDensity));
  const auto* pieces = scratch.Pieces.data();
  const auto* cumulative = scratch.Cumulative.data();
  for (int q = 0; q < 200; ++q)
  {
    const Vec<2> x = RandomVec<2>(gen, -0.1, 0.1); // B(x, 0.25) inside B(0, 0.5)
    curve.SampleInBall(x, 0.25, rng, scratch, z, &strength, inverseDensity);
    ASSERT_EQ(scratch.Pieces.data(), pieces);
    ASSERT_EQ(scratch.Cumulative.data(), cumulative);
  }
}
} // namespace
