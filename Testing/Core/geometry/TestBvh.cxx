// Tests of the closest-point kernels and of the BVH against brute force.
//
// The BVH must return what a brute-force minimum over all primitives returns
// (it evaluates the same kernels, so up to their last-bit rounding), for any
// input a mesh file can hold: degenerate, duplicated and repeated-vertex
// primitives included. Seeds are fixed, so failures are reproducible.
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/Vector.h>

#include "RandomSoups.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using gridfree::Bvh;
using gridfree::testing::BruteForceSquaredDistance;
using gridfree::testing::KernelClosest;
using gridfree::testing::MakeSoup;
using gridfree::testing::Soup;
using gridfree::ClosestPointOnSegment;
using gridfree::ClosestPointOnTriangle;
using gridfree::Vec;
using gridfree::Vec2;
using gridfree::Vec3;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Queries inside the box, near the primitives (down to exactly on them) and
/// far outside.
template <int DIM>
std::vector<Vec<DIM>> MakeQueries(const Soup<DIM>& soup, int perKind, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss;
  gridfree::BoundingBox<DIM> box;
  for (const auto& v : soup.Vertices)
  {
    box.Expand(v);
  }
  const double diag = std::max(box.Diagonal(), 1e-3);
  auto direction = [&]()
  {
    Vec<DIM> d;
    for (int k = 0; k < DIM; ++k)
    {
      d[k] = gauss(rng);
    }
    return Vec<DIM>(d.normalized());
  };

  std::vector<Vec<DIM>> queries;
  for (int i = 0; i < perKind; ++i)
  {
    // Inside the (slightly enlarged) box.
    Vec<DIM> q;
    for (int k = 0; k < DIM; ++k)
    {
      q[k] = box.Min[k] - 0.05 * diag + (box.Max[k] - box.Min[k] + 0.1 * diag) * u01(rng);
    }
    queries.push_back(q);

    // Near a random primitive: a point of it, offset by 0 to 1e-2 of the box.
    const auto& prim = soup.Primitives[rng() % soup.Primitives.size()];
    Vec<DIM> w;
    for (int k = 0; k < DIM; ++k)
    {
      w[k] = u01(rng);
    }
    w /= w.sum();
    Vec<DIM> p = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      p += w[k] * soup.Vertices[prim[k]];
    }
    const int mode = i % 4;
    if (mode == 0)
    {
      queries.push_back(soup.Vertices[prim[rng() % DIM]]); // exactly on a vertex
    }
    else
    {
      const double offset = (mode == 1) ? 0.0 : diag * std::pow(10.0, -10.0 + 8.0 * u01(rng));
      queries.push_back(p + offset * direction());
    }

    // Far outside.
    queries.push_back(box.Center() + diag * (2.0 + 100.0 * u01(rng)) * direction());
  }
  return queries;
}

//------------------------------------------------------------------------------
/// Checks one query of a BVH against brute force.
template <int DIM>
void CheckQuery(const Bvh<DIM>& bvh, const Soup<DIM>& soup, const Vec<DIM>& x, double scale)
{
  const double ref2 = BruteForceSquaredDistance(soup, x);
  const double ref = std::sqrt(ref2);
  const double tol = 1e-12 * ref + 1e-14 * scale;

  const double d = bvh.Distance(x);
  ASSERT_NEAR(d, ref, tol) << "query " << x.transpose();
  EXPECT_NEAR(bvh.SquaredDistance(x), ref2, (2.0 * ref + tol) * tol);

  const gridfree::ClosestPointResult<DIM> r = bvh.ClosestPoint(x);
  ASSERT_GE(r.primitive, 0);
  ASSERT_LT(r.primitive, static_cast<std::int64_t>(soup.Primitives.size()));
  EXPECT_NEAR(r.distance, ref, tol);
  EXPECT_NEAR((x - r.point).norm(), r.distance, tol);

  // The reported primitive (an ORIGINAL index) really holds the point.
  const auto own = KernelClosest(soup, static_cast<std::size_t>(r.primitive), x);
  EXPECT_NEAR(std::sqrt(own.squaredDistance), ref, tol);
  EXPECT_LE((own.point - r.point).norm(), 1e-12 * scale);

  // Up to ties, the point is the brute-force one: it must be the closest point
  // of some primitive that achieves the minimum.
  bool matched = false;
  for (std::size_t p = 0; p < soup.Primitives.size() && !matched; ++p)
  {
    const auto c = KernelClosest(soup, p, x);
    matched = std::abs(std::sqrt(c.squaredDistance) - ref) <= tol &&
      (c.point - r.point).norm() <= 1e-12 * scale;
  }
  EXPECT_TRUE(matched) << "query " << x.transpose();

  // Barycentric weights: in [0, 1], sum to 1, reproduce the point.
  const auto& prim = soup.Primitives[r.primitive];
  Vec<DIM> interpolated = Vec<DIM>::Zero();
  for (int k = 0; k < DIM; ++k)
  {
    EXPECT_GE(r.barycentric[k], 0.0);
    EXPECT_LE(r.barycentric[k], 1.0);
    interpolated += r.barycentric[k] * soup.Vertices[prim[k]];
  }
  EXPECT_NEAR(r.barycentric.sum(), 1.0, 1e-12);
  EXPECT_LE((interpolated - r.point).norm(), 1e-12 * scale);
}

template <int DIM>
void CheckSoup(int n, std::uint64_t seed, int queriesPerKind)
{
  const Soup<DIM> soup = MakeSoup<DIM>(n, seed);
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_FALSE(bvh.Empty());
  ASSERT_EQ(bvh.NumberOfPrimitives(), soup.Primitives.size());
  ASSERT_TRUE(bvh.Validate());

  gridfree::BoundingBox<DIM> box;
  for (const auto& prim : soup.Primitives)
  {
    for (const auto v : prim)
    {
      box.Expand(soup.Vertices[v]);
    }
  }
  EXPECT_EQ(bvh.Bounds().Min, box.Min);
  EXPECT_EQ(bvh.Bounds().Max, box.Max);

  const double scale = std::max(box.Diagonal(), 1.0);
  for (const auto& x : MakeQueries(soup, queriesPerKind, seed + 1000))
  {
    CheckQuery(bvh, soup, x, scale + x.norm());
    if (::testing::Test::HasFatalFailure())
    {
      return;
    }
  }
}

//------------------------------------------------------------------------------
// Kernels on known configurations.
TEST(ClosestPointPrimitives, SegmentRegions)
{
  const Vec2 a(0, 0), b(2, 0);
  auto r = ClosestPointOnSegment<2>(Vec2(1, 1), a, b); // interior
  EXPECT_DOUBLE_EQ(r.point.x(), 1.0);
  EXPECT_DOUBLE_EQ(r.point.y(), 0.0);
  EXPECT_DOUBLE_EQ(r.squaredDistance, 1.0);
  EXPECT_DOUBLE_EQ(r.weights[0], 0.5);
  EXPECT_DOUBLE_EQ(r.weights[1], 0.5);

  r = ClosestPointOnSegment<2>(Vec2(-1, 1), a, b); // before a: exactly a
  EXPECT_EQ(r.point, a);
  EXPECT_EQ(r.weights, Vec2(1, 0));
  EXPECT_DOUBLE_EQ(r.squaredDistance, 2.0);

  r = ClosestPointOnSegment<2>(Vec2(5, -4), a, b); // after b: exactly b
  EXPECT_EQ(r.point, b);
  EXPECT_EQ(r.weights, Vec2(0, 1));
  EXPECT_DOUBLE_EQ(r.squaredDistance, 25.0);

  const auto r3 = ClosestPointOnSegment<3>(Vec3(1, 2, 3), Vec3(0, 0, 0), Vec3(0, 0, 4));
  EXPECT_EQ(r3.point, Vec3(0, 0, 3));
  EXPECT_DOUBLE_EQ(r3.weights[1], 0.75);
  EXPECT_DOUBLE_EQ(r3.squaredDistance, 5.0);
}

TEST(ClosestPointPrimitives, ZeroLengthSegment)
{
  const Vec3 a(1, 1, 1);
  const auto r = ClosestPointOnSegment<3>(Vec3(1, 1, 3), a, a);
  EXPECT_EQ(r.point, a);
  EXPECT_EQ(r.weights[0] + r.weights[1], 1.0);
  EXPECT_DOUBLE_EQ(r.squaredDistance, 4.0);
  EXPECT_EQ(gridfree::SquaredDistanceToSegment<3>(Vec3(1, 1, 3), a, a), 4.0);

  // Tiny (underflowing) length: still the point, never NaN.
  const Vec2 b(0, 0), c(1e-170, 0);
  const auto t = ClosestPointOnSegment<2>(Vec2(3, 4), b, c);
  EXPECT_FALSE(std::isnan(t.squaredDistance));
  EXPECT_DOUBLE_EQ(t.squaredDistance, 25.0);
}

TEST(ClosestPointPrimitives, TriangleRegions)
{
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case
  {
    Vec3 X, Point, Weights;
  };
  const Case cases[] = {
    { Vec3(0.25, 0.25, 2), Vec3(0.25, 0.25, 0), Vec3(0.5, 0.25, 0.25) },  // face
    { Vec3(0.25, 0.25, -3), Vec3(0.25, 0.25, 0), Vec3(0.5, 0.25, 0.25) }, // face, below
    { Vec3(-1, -1, 1), a, Vec3(1, 0, 0) },                                // vertex a
    { Vec3(3, -1, 0), b, Vec3(0, 1, 0) },                                 // vertex b
    { Vec3(-0.5, 4, 1), c, Vec3(0, 0, 1) },                               // vertex c
    { Vec3(0.5, -2, 1), Vec3(0.5, 0, 0), Vec3(0.5, 0.5, 0) },             // edge ab
    { Vec3(-2, 0.25, 0), Vec3(0, 0.25, 0), Vec3(0.75, 0, 0.25) },         // edge ca
    { Vec3(1, 1, 0.5), Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0.5) },            // edge bc
    { Vec3(0, 0, 0), a, Vec3(1, 0, 0) },                                  // on a vertex
  };
  for (const auto& tc : cases)
  {
    const auto r = ClosestPointOnTriangle(tc.X, a, b, c);
    EXPECT_LE((r.point - tc.Point).norm(), 1e-15) << tc.X.transpose();
    EXPECT_LE((r.weights - tc.Weights).norm(), 1e-15) << tc.X.transpose();
    EXPECT_NEAR(r.squaredDistance, (tc.X - tc.Point).squaredNorm(), 1e-15);
    EXPECT_EQ(gridfree::SquaredDistanceToTriangle(tc.X, a, b, c), r.squaredDistance);
  }
}

TEST(ClosestPointPrimitives, DegenerateTriangles)
{
  auto check = [](const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& expected)
  {
    const auto r = ClosestPointOnTriangle(x, a, b, c);
    EXPECT_FALSE(r.point.hasNaN());
    EXPECT_FALSE(r.weights.hasNaN());
    EXPECT_LE((r.point - expected).norm(), 1e-14) << x.transpose();
    EXPECT_NEAR(r.weights.sum(), 1.0, 1e-15);
    EXPECT_GE(r.weights.minCoeff(), 0.0);
    EXPECT_LE((r.weights[0] * a + r.weights[1] * b + r.weights[2] * c - r.point).norm(), 1e-14);
  };
  const Vec3 a(0, 0, 0), b(2, 0, 0), m(1, 0, 0), p(4, 0, 0);
  // Collinear, third vertex between the others and beyond them.
  check(Vec3(1.5, 1, 0), a, b, m, Vec3(1.5, 0, 0));
  check(Vec3(3, 0, -1), a, b, p, Vec3(3, 0, 0));
  check(Vec3(5, 1, 1), a, b, p, p);
  check(Vec3(-1, 1, 0), m, b, a, a);
  // Two identical vertices: a segment.
  check(Vec3(1, 0, 2), a, a, b, Vec3(1, 0, 0));
  check(Vec3(1, 0, 2), b, a, a, Vec3(1, 0, 0));
  check(Vec3(1, 0, 2), a, b, a, Vec3(1, 0, 0));
  // Three identical vertices: a point.
  check(Vec3(1, 2, 3), m, m, m, m);
  // Collinear up to rounding, far from the origin.
  const Vec3 o(1e3, -2e3, 5e2), d(0.1, 0.7, 0.3);
  check(o + d * 0.5 + Vec3(0.7, -0.1, 0).normalized(), o, o + d, o + d * 0.3, o + d * 0.5);
}

TEST(ClosestPointPrimitives, BoundedTriangleDistance)
{
  // The early-out version either returns the full kernel's value or +inf,
  // and +inf only when the distance is not below the bound.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int skipped = 0;
  for (int i = 0; i < 100000; ++i)
  {
    const Vec3 a(u(rng), u(rng), u(rng));
    const Vec3 b = a + std::pow(10.0, -3.0 * std::abs(u(rng))) * Vec3(u(rng), u(rng), u(rng));
    const Vec3 c = (i % 10 == 0) ? Vec3(a + 0.5 * (b - a)) // degenerate
                                 : Vec3(a + Vec3(u(rng), u(rng), u(rng)));
    // Queries near the plane, exactly on it, or anywhere.
    Vec3 x = Vec3(u(rng), u(rng), u(rng));
    if (i % 3 == 0)
    {
      x = a + 0.3 * (b - a) + 0.2 * (c - a) + 1e-12 * u(rng) * (b - a).cross(c - a);
    }
    const double full = gridfree::SquaredDistanceToTriangle(x, a, b, c);
    // Bounds straddling the true value, down to relative differences ~1e-15,
    // or well below it.
    const double bound = (i % 4 == 3)
      ? full * std::abs(u(rng))
      : full * (1.0 + std::pow(10.0, -15.0 + 14.0 * std::abs(u(rng))) * ((i % 2) ? 1.0 : -1.0));
    const double bounded = gridfree::SquaredDistanceToTriangle(x, a, b, c, bound);
    if (bounded == kInf)
    {
      ++skipped;
      EXPECT_GE(full, bound * (1.0 - 1e-12) - 1e-30) << i;
    }
    else
    {
      EXPECT_EQ(bounded, full) << i;
    }
    EXPECT_EQ(gridfree::SquaredDistanceToTriangle(x, a, b, c, kInf), full);
  }
  EXPECT_GT(skipped, 1000); // the early out does happen
}

TEST(ClosestPointPrimitives, ThinTrianglesAreAccurate)
{
  // Slivers down to ~1e-7 aspect ratio: compare with a long double reference
  // (projection when inside, else the best edge).
  using LVec = Eigen::Matrix<long double, 3, 1>;
  auto segment = [](const LVec& x, const LVec& a, const LVec& b)
  {
    const LVec ab = b - a;
    const long double len2 = ab.squaredNorm();
    long double t = len2 > 0 ? ab.dot(x - a) / len2 : 0;
    t = std::min<long double>(std::max<long double>(t, 0), 1);
    return (x - (a + t * ab)).squaredNorm();
  };
  auto reference = [&](const LVec& x, const LVec& a, const LVec& b, const LVec& c)
  {
    const LVec n = (b - a).cross(c - a);
    const long double nn = n.squaredNorm();
    const LVec p = x - n * (n.dot(x - a) / nn);
    const long double u = n.dot((c - b).cross(p - b)) / nn;
    const long double v = n.dot((a - c).cross(p - c)) / nn;
    const long double w = n.dot((b - a).cross(p - a)) / nn;
    if (u >= 0 && v >= 0 && w >= 0)
    {
      return (x - p).squaredNorm();
    }
    return std::min({ segment(x, a, b), segment(x, b, c), segment(x, c, a) });
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i)
  {
    const Vec3 a(u(rng), u(rng), u(rng));
    const Vec3 b(u(rng), u(rng), u(rng));
    const double thinness = std::pow(10.0, -7.0 * (0.5 + 0.5 * u(rng)));
    const Vec3 c =
      0.5 * (a + b) + thinness * Vec3(u(rng), u(rng), u(rng)) + (0.3 * u(rng)) * (b - a);
    const Vec3 x = Vec3(u(rng), u(rng), u(rng)) * ((i % 3 == 0) ? 1e-3 : 1.0) +
      ((i % 3 == 0) ? Vec3(0.5 * (a + b)) : Vec3::Zero());
    const double d = std::sqrt(ClosestPointOnTriangle(x, a, b, c).squaredDistance);
    const double ref = std::sqrt(static_cast<double>(reference(
      x.cast<long double>(), a.cast<long double>(), b.cast<long double>(), c.cast<long double>())));
    ASSERT_NEAR(d, ref, 1e-9) << i;
  }
}

//------------------------------------------------------------------------------
// BVH against brute force.
TEST(Bvh, EmptyHierarchy)
{
  Bvh<3> bvh;
  EXPECT_TRUE(bvh.Empty());
  EXPECT_EQ(bvh.NumberOfPrimitives(), 0u);
  EXPECT_EQ(bvh.Distance(Vec3(1, 2, 3)), kInf);
  auto r = bvh.ClosestPoint(Vec3(1, 2, 3));
  EXPECT_EQ(r.primitive, -1);
  EXPECT_EQ(r.distance, kInf);
  EXPECT_TRUE(bvh.Validate());

  bvh.Build({ Vec3(0, 0, 0) }, {}); // vertices but no primitive
  EXPECT_TRUE(bvh.Empty());
  EXPECT_EQ(bvh.Distance(Vec3(0, 0, 0)), kInf);
  EXPECT_TRUE(bvh.Bounds().IsEmpty());

  Bvh<2> bvh2;
  EXPECT_EQ(bvh2.Distance(Vec2(0, 0)), kInf);
  EXPECT_EQ(bvh2.ClosestPoint(Vec2(0, 0)).primitive, -1);
}

TEST(Bvh, RejectsInvalidIndices)
{
  Bvh<3> bvh;
  const std::vector<Vec3> v = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0) };
  EXPECT_THROW(bvh.Build(v, { { 0, 1, 3 } }), std::out_of_range);
  EXPECT_THROW(bvh.Build(v, { { 0, -1, 2 } }), std::out_of_range);
}

TEST(Bvh, ReportsOriginalPrimitiveIndices)
{
  // A row of unit triangles along x, given in shuffled order: the one under a
  // query must be reported by its index in the input array.
  std::vector<Vec3> v;
  std::vector<Bvh<3>::Primitive> t;
  std::vector<int> slot(500);
  for (int i = 0; i < 500; ++i)
  {
    slot[i] = (i * 263) % 500; // a permutation of positions
  }
  for (int i = 0; i < 500; ++i)
  {
    const double x0 = 2.0 * slot[i];
    v.emplace_back(x0, 0, 0);
    v.emplace_back(x0 + 1, 0, 0);
    v.emplace_back(x0, 1, 0);
    const auto base = static_cast<std::int64_t>(v.size()) - 3;
    t.push_back({ base, base + 1, base + 2 });
  }
  Bvh<3> bvh;
  bvh.Build(v, t);
  for (int i = 0; i < 500; ++i)
  {
    const Vec3 q(2.0 * slot[i] + 0.25, 0.25, 0.5);
    const auto r = bvh.ClosestPoint(q);
    ASSERT_EQ(r.primitive, i);
    EXPECT_DOUBLE_EQ(r.distance, 0.5);
    EXPECT_NEAR(r.barycentric[0], 0.5, 1e-15);
    EXPECT_NEAR(r.barycentric[1], 0.25, 1e-15);
    EXPECT_NEAR(r.barycentric[2], 0.25, 1e-15);
  }
}

TEST(Bvh, SinglePrimitiveAndRebuild)
{
  Bvh<3> bvh;
  bvh.Build({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0) }, { { 0, 1, 2 } });
  EXPECT_EQ(bvh.NumberOfPrimitives(), 1u);
  EXPECT_DOUBLE_EQ(bvh.Distance(Vec3(0.2, 0.2, -2)), 2.0);
  // Rebuilding replaces the content.
  bvh.Build({ Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5), Vec3(0, 0, 9) }, { { 3, 3, 3 } });
  EXPECT_EQ(bvh.NumberOfPrimitives(), 1u);
  EXPECT_DOUBLE_EQ(bvh.Distance(Vec3(0, 0, 0)), 9.0);
  EXPECT_EQ(bvh.Bounds().Min, Vec3(0, 0, 9));
  EXPECT_EQ(bvh.ClosestPoint(Vec3(0, 0, 0)).primitive, 0);
}

TEST(Bvh, TriangleSoups)
{
  std::uint64_t seed = 11;
  for (const int n : { 1, 2, 7, 1000, 20000 })
  {
    SCOPED_TRACE(n);
    CheckSoup<3>(n, seed++, n < 1000 ? 200 : 120);
  }
}

TEST(Bvh, SegmentSoups)
{
  std::uint64_t seed = 21;
  for (const int n : { 1, 2, 7, 1000, 20000 })
  {
    SCOPED_TRACE(n);
    CheckSoup<2>(n, seed++, n < 1000 ? 200 : 120);
  }
}

TEST(Bvh, FlatAndOffsetGeometry)
{
  // Boxes with zero extent along an axis, far from the origin, stress the
  // outward rounding of the compressed node boxes.
  Soup<3> soup = MakeSoup<3>(3000, 99);
  for (auto& v : soup.Vertices)
  {
    v = Vec3(1e6 + v.x(), -3e5 + 1e-3 * v.y(), 7.0); // flat in z, thin in y
  }
  Bvh<3> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  const double scale = 2e6;
  for (const auto& x : MakeQueries(soup, 60, 5))
  {
    CheckQuery(bvh, soup, x, scale);
    ASSERT_FALSE(HasFatalFailure());
  }

  Soup<2> soup2 = MakeSoup<2>(3000, 98);
  for (auto& v : soup2.Vertices)
  {
    v = Vec2(-4e7 + v.x(), 1.5); // all segments on one horizontal line
  }
  Bvh<2> bvh2;
  bvh2.Build(soup2.Vertices, soup2.Primitives);
  ASSERT_TRUE(bvh2.Validate());
  for (const auto& x : MakeQueries(soup2, 60, 6))
  {
    CheckQuery(bvh2, soup2, x, 1e8);
    ASSERT_FALSE(HasFatalFailure());
  }
}

template <int DIM>
void CheckNearTies(std::uint64_t seed)
{
  // Tiny primitives tangent to the unit sphere around q, at distances
  // 1 + i * 1e-12 in random directions. Their boxes are far tighter than float
  // precision, so any box bound that is not a true lower bound prunes the
  // winner (index 0) and fails the test.
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  const Vec<DIM> q = Vec<DIM>::Constant(0.3) + Vec<DIM>::Unit(0) * 123.0;
  const int n = 3000;
  Soup<DIM> soup;
  for (int i = 0; i < n; ++i)
  {
    Vec<DIM> u;
    for (int k = 0; k < DIM; ++k)
    {
      u[k] = gauss(rng);
    }
    u.normalize();
    const Vec<DIM> c = q + (1.0 + i * 1e-12) * u;
    // Unit vectors spanning the tangent plane.
    Vec<DIM> e1 = Vec<DIM>::Unit(std::abs(u[0]) < 0.5 ? 0 : 1);
    e1 = (e1 - e1.dot(u) * u).normalized();
    typename Bvh<DIM>::Primitive prim;
    const double s = 1e-7;
    if constexpr (DIM == 2)
    {
      soup.Vertices.push_back(c - s * e1);
      soup.Vertices.push_back(c + s * e1);
    }
    else
    {
      const Vec3 e2 = u.cross(e1);
      for (int k = 0; k < 3; ++k)
      {
        const double angle = 2.0 * std::acos(-1.0) * k / 3.0;
        soup.Vertices.push_back(c + s * (std::cos(angle) * e1 + std::sin(angle) * e2));
      }
    }
    for (int k = 0; k < DIM; ++k)
    {
      prim[k] = static_cast<std::int64_t>(soup.Vertices.size()) - DIM + k;
    }
    soup.Primitives.push_back(prim);
  }
  // Shuffle so that the winner is not first in the input.
  std::vector<std::int64_t> perm(n);
  for (int i = 0; i < n; ++i)
  {
    perm[i] = i;
  }
  std::shuffle(perm.begin(), perm.end(), rng);
  Soup<DIM> shuffled{ soup.Vertices, {} };
  for (int i = 0; i < n; ++i)
  {
    shuffled.Primitives.push_back(soup.Primitives[perm[i]]);
  }
  const auto winner = std::find(perm.begin(), perm.end(), 0) - perm.begin();

  Bvh<DIM> bvh;
  bvh.Build(shuffled.Vertices, shuffled.Primitives);
  ASSERT_TRUE(bvh.Validate());
  const auto r = bvh.ClosestPoint(q);
  EXPECT_EQ(r.primitive, winner);
  EXPECT_NEAR(r.distance, 1.0, 1e-13);
  EXPECT_EQ(bvh.Distance(q), r.distance);
  CheckQuery(bvh, shuffled, q, 200.0);
}

template <int DIM>
void CheckTightClusters(std::uint64_t seed)
{
  // Clusters of tiny primitives (1e-3 down to 1e-12 across) spread over
  // [-1000, 1000]: deep nodes are far smaller than a float ulp of their
  // position, where the outward rounding of the node boxes is most delicate.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto randomPoint = [&]()
  {
    Vec<DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = u(rng);
    }
    return p;
  };
  Soup<DIM> soup;
  for (int cluster = 0; cluster < 400; ++cluster)
  {
    const Vec<DIM> center = 1000.0 * randomPoint();
    const double size = std::pow(10.0, -7.5 + 4.5 * u(rng));
    for (int i = 0; i < 10; ++i)
    {
      typename Bvh<DIM>::Primitive prim;
      for (int k = 0; k < DIM; ++k)
      {
        soup.Vertices.push_back(center + size * randomPoint());
        prim[k] = static_cast<std::int64_t>(soup.Vertices.size()) - 1;
      }
      soup.Primitives.push_back(prim);
    }
  }
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  for (int i = 0; i < 100; ++i)
  {
    // Right next to a cluster, where its tight boxes decide the answer.
    const auto& prim = soup.Primitives[rng() % soup.Primitives.size()];
    const Vec<DIM> x = soup.Vertices[prim[0]] + 1e-9 * randomPoint();
    CheckQuery(bvh, soup, x, 2000.0);
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
  }
}

TEST(Bvh, TightClusters)
{
  CheckTightClusters<3>(31);
  CheckTightClusters<2>(32);
}

TEST(Bvh, NearTiesAreResolvedExactly)
{
  CheckNearTies<3>(1);
  CheckNearTies<2>(2);
}

TEST(Bvh, ClosedSurface)
{
  // A closed, regular surface (octahedron refined to 8 * 4^5 triangles, on the
  // unit sphere): the typical walk-on-spheres boundary, queried inside.
  std::vector<Vec3> v = { Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
    Vec3(0, 0, 1), Vec3(0, 0, -1) };
  std::vector<Bvh<3>::Primitive> t = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 },
    { 2, 0, 5 }, { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
  for (int level = 0; level < 5; ++level)
  {
    std::vector<Bvh<3>::Primitive> refined;
    for (const auto& f : t)
    {
      std::int64_t m[3];
      for (int k = 0; k < 3; ++k)
      {
        v.push_back((0.5 * (v[f[k]] + v[f[(k + 1) % 3]])).normalized());
        m[k] = static_cast<std::int64_t>(v.size()) - 1; // duplicated midpoints are fine
      }
      refined.push_back({ f[0], m[0], m[2] });
      refined.push_back({ f[1], m[1], m[0] });
      refined.push_back({ f[2], m[2], m[1] });
      refined.push_back({ m[0], m[1], m[2] });
    }
    t.swap(refined);
  }
  Soup<3> soup{ v, t };
  Bvh<3> bvh;
  bvh.Build(v, t);
  ASSERT_TRUE(bvh.Validate());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 300; ++i)
  {
    CheckQuery(bvh, soup, Vec3(u(rng), u(rng), u(rng)), 2.0);
    ASSERT_FALSE(HasFatalFailure());
  }
  CheckQuery(bvh, soup, Vec3(0, 0, 0), 2.0); // equidistant from everything
}

// Adversarial: every primitive at exactly the same distance from the query.
// A fan of triangles (segments in 2D) around one apex vertex, the query on
// the axis above the apex, is closest to every one of them at that shared
// vertex: the distances are bit-identical, so nothing can be pruned by a
// strictly better candidate and any box bound that is not a true lower bound
// would lose the tie. Also a sphere of tiny primitives, each touching the
// sphere of radius 1 around the query at a vertex on an axis-aligned grid
// of directions, where the kernel's rounding is the same for all.
TEST(Bvh, AllPrimitivesEquidistant)
{
  {
    Soup<3> fan;
    fan.Vertices.push_back(Vec3(0.25, -0.5, 1.0)); // the apex
    const int n = 4000;
    for (int i = 0; i < n; ++i)
    {
      const double a = 2.0 * M_PI * i / n;
      const double b = 2.0 * M_PI * (i + 1) / n;
      // The rim sinks below the apex plane so the apex stays closest.
      fan.Vertices.push_back(fan.Vertices[0] + Vec3(std::cos(a), std::sin(a), -0.5));
      fan.Vertices.push_back(fan.Vertices[0] + Vec3(std::cos(b), std::sin(b), -0.5));
      fan.Primitives.push_back({ 0, 2 * i + 1, 2 * i + 2 });
    }
    Bvh<3> bvh;
    bvh.Build(fan.Vertices, fan.Primitives);
    ASSERT_TRUE(bvh.Validate());
    for (const double h : { 1e-9, 0.01, 0.3, 7.0 })
    {
      const Vec3 q = fan.Vertices[0] + Vec3(0, 0, h);
      const double ref2 = BruteForceSquaredDistance(fan, q);
      EXPECT_EQ(bvh.SquaredDistance(q), ref2) << "height " << h;
      const auto r = bvh.ClosestPoint(q);
      EXPECT_EQ(r.point, fan.Vertices[0]) << "height " << h;
      CheckQuery(bvh, fan, q, 2.0);
    }
  }
  {
    Soup<2> fan;
    fan.Vertices.push_back(Vec2(-3.0, 2.0));
    const int n = 4000;
    for (int i = 0; i < n; ++i)
    {
      // Segments leaving the apex downwards, in the lower half-plane only.
      const double a = M_PI * (1.0 + (i + 0.5) / n);
      fan.Vertices.push_back(fan.Vertices[0] + Vec2(std::cos(a), std::sin(a)));
      fan.Primitives.push_back({ 0, i + 1 });
    }
    Bvh<2> bvh;
    bvh.Build(fan.Vertices, fan.Primitives);
    ASSERT_TRUE(bvh.Validate());
    for (const double h : { 1e-9, 0.5, 4.0 })
    {
      const Vec2 q = fan.Vertices[0] + Vec2(0, h);
      EXPECT_EQ(bvh.SquaredDistance(q), BruteForceSquaredDistance(fan, q)) << "height " << h;
      CheckQuery(bvh, fan, q, 2.0);
    }
  }
  {
    // Tiny triangles with one vertex exactly at distance 1 from q along the
    // ±x, ±y, ±z directions and the 12 (±1, ±1, 0)-type diagonals scaled by
    // powers of two (exact), the rest of the triangle farther out.
    const Vec3 q(0.5, 0.25, -0.125);
    Soup<3> shell;
    std::vector<Vec3> dirs;
    for (int k = 0; k < 3; ++k)
    {
      for (const double sgn : { -1.0, 1.0 })
      {
        dirs.push_back(sgn * Vec3::Unit(k));
      }
    }
    for (const Vec3& d : dirs)
    {
      for (int copy = 0; copy < 200; ++copy)
      {
        const Vec3 apex = q + d;
        // Two tangent vectors, and an outward tilt so the apex is closest.
        const Vec3 t1 = Vec3::Unit((d.cwiseAbs().maxCoeff() == std::abs(d[0])) ? 1 : 0);
        const Vec3 t2 = d.cross(t1);
        const double s = 1e-3 * (1 + copy % 7);
        const auto base = static_cast<std::int64_t>(shell.Vertices.size());
        shell.Vertices.push_back(apex);
        shell.Vertices.push_back(apex + s * (t1 + d));
        shell.Vertices.push_back(apex + s * (t2 + d));
        shell.Primitives.push_back({ base, base + 1, base + 2 });
      }
    }
    Bvh<3> bvh;
    bvh.Build(shell.Vertices, shell.Primitives);
    ASSERT_TRUE(bvh.Validate());
    EXPECT_EQ(bvh.SquaredDistance(q), 1.0);
    EXPECT_EQ(BruteForceSquaredDistance(shell, q), 1.0);
    CheckQuery(bvh, shell, q, 2.0);
  }
}

// Adversarial: coplanar, overlapping and duplicated triangles (a polygon soup
// of layered patches, as from concatenated meshes), queried on the plane,
// just off it and far from it; and collinear overlapping segments in 2D.
TEST(Bvh, CoplanarOverlappingPrimitives)
{
  std::mt19937_64 rng(404);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  {
    Soup<3> soup;
    for (int i = 0; i < 3000; ++i)
    {
      const auto base = static_cast<std::int64_t>(soup.Vertices.size());
      const Vec3 c(u(rng), u(rng), 0.0);
      const double s = 0.05 + 0.3 * std::abs(u(rng));
      for (int k = 0; k < 3; ++k)
      {
        soup.Vertices.push_back(c + s * Vec3(u(rng), u(rng), 0.0));
      }
      soup.Primitives.push_back({ base, base + 1, base + 2 });
      if (i % 5 == 0) // an exact duplicate, in another vertex order
      {
        soup.Primitives.push_back({ base + 2, base, base + 1 });
      }
    }
    Bvh<3> bvh;
    bvh.Build(soup.Vertices, soup.Primitives);
    ASSERT_TRUE(bvh.Validate());
    for (int i = 0; i < 200; ++i)
    {
      const double z = (i % 4 == 0) ? 0.0 : (i % 4 == 1 ? 1e-12 : (i % 4 == 2 ? -0.01 : 3.0));
      CheckQuery(bvh, soup, Vec3(1.3 * u(rng), 1.3 * u(rng), z), 3.0);
      ASSERT_FALSE(HasFatalFailure());
    }
  }
  {
    Soup<2> soup;
    for (int i = 0; i < 2000; ++i)
    {
      const auto base = static_cast<std::int64_t>(soup.Vertices.size());
      const double a = u(rng), b = a + 0.2 * std::abs(u(rng));
      soup.Vertices.push_back(Vec2(a, 0.5 * a)); // all on the line y = x / 2
      soup.Vertices.push_back(Vec2(b, 0.5 * b));
      soup.Primitives.push_back({ base, base + 1 });
    }
    Bvh<2> bvh;
    bvh.Build(soup.Vertices, soup.Primitives);
    ASSERT_TRUE(bvh.Validate());
    for (int i = 0; i < 200; ++i)
    {
      const double x = 1.5 * u(rng);
      const double off = (i % 3 == 0) ? 0.0 : 0.1 * u(rng);
      CheckQuery(bvh, soup, Vec2(x, 0.5 * x + off), 3.0);
      ASSERT_FALSE(HasFatalFailure());
    }
  }
}

// The relaxed lower bound of walk steps: never above the exact distance, never
// below 1 / (1 + relaxation) of it, and equal to it when flagged exact. (A
// distance below `exactBelow` need not be exact: boxes skipped while the
// nearest triangle found was still farther stay skipped.)
template <int DIM>
void CheckDistanceLowerBound(const Soup<DIM>& soup, const std::vector<Vec<DIM>>& queries)
{
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  int relaxed = 0;
  for (const double relaxation : { 0.05, 0.2, 1.0 })
  {
    for (const double exactBelow : { 0.0, 0.01, 0.1 })
    {
      for (const auto& x : queries)
      {
        const double d = bvh.Distance(x);
        bool exact = false;
        const double bound = bvh.DistanceLowerBound(x, relaxation, exactBelow, exact);
        ASSERT_LE(bound, d) << "query " << x.transpose();
        ASSERT_GE(bound, d / (1.0 + relaxation) * (1.0 - 1e-6)) << "query " << x.transpose();
        if (exact)
        {
          ASSERT_EQ(bound, d) << "query " << x.transpose();
        }
        relaxed += bound < d ? 1 : 0;
      }
    }
  }
  // The relaxation must actually happen somewhere, or the test shows nothing.
  EXPECT_GT(relaxed, 0);
}

// Queries that carry a NearestHint from one to the next, as a walk does
// (consecutive points one ball radius apart, and hints left by unrelated or
// far-away queries): exact queries answer as brute force does, relaxed ones
// stay within their bound, and a closest point after an exact step that
// proved its primitive nearest is that of brute force.
template <int DIM>
void CheckHintedQueries(const Soup<DIM>& soup, const std::vector<Vec<DIM>>& queries)
{
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  std::mt19937_64 rng(91);
  std::normal_distribution<double> gauss;
  typename Bvh<DIM>::NearestHint hint;
  int reused = 0;
  for (const auto& start : queries)
  {
    Vec<DIM> x = start;
    for (int step = 0; step < 8; ++step)
    {
      const double d2 = BruteForceSquaredDistance(soup, x);
      const double d = std::sqrt(d2);
      bool exact = false;
      const double bound = bvh.DistanceLowerBound(x, 0.2, 0.01, exact, &hint);
      ASSERT_LE(bound, d) << "query " << x.transpose();
      ASSERT_GE(bound, d / 1.2 * (1.0 - 1e-6)) << "query " << x.transpose();
      ASSERT_GE(hint.Primitive, 0);
      if (exact)
      {
        ASSERT_EQ(bound, d) << "query " << x.transpose();
        // The closest point then comes from the hint alone.
        const auto hit = bvh.ClosestPoint(x, hint);
        ASSERT_EQ(hit.distance, d) << "query " << x.transpose();
        ASSERT_EQ(KernelClosest(soup, static_cast<std::size_t>(hit.primitive), x).squaredDistance, d2);
        ++reused;
      }
      ASSERT_EQ(bvh.SquaredDistance(x, hint), d2) << "query " << x.transpose();
      ASSERT_TRUE(hint.Exact);
      ASSERT_EQ(bvh.ClosestPoint(x, hint).distance, bvh.ClosestPoint(x).distance);
      // The next point: one step of the exact radius in a random direction.
      Vec<DIM> dir;
      for (int k = 0; k < DIM; ++k)
      {
        dir[k] = gauss(rng);
      }
      x += d * dir.normalized();
    }
  }
  EXPECT_GT(reused, 0);
  // A stale hint (a point elsewhere, not proved) or one out of range is only
  // a starting guess: answers are unchanged.
  typename Bvh<DIM>::NearestHint stale;
  // (Leaves take whole groups of four slots, so there are fewer than 4n.)
  stale.Primitive = 4 * static_cast<std::int64_t>(soup.Primitives.size()) + 5;
  stale.Exact = true;
  stale.Point = queries.front();
  for (const auto& x : queries)
  {
    ASSERT_EQ(bvh.ClosestPoint(x, stale).distance, bvh.ClosestPoint(x).distance);
  }
}

TEST(Bvh, HintedQueriesMatchBruteForce)
{
  CheckHintedQueries<3>(MakeSoup<3>(2000, 81), MakeQueries(MakeSoup<3>(2000, 81), 30, 82));
  CheckHintedQueries<2>(MakeSoup<2>(2000, 83), MakeQueries(MakeSoup<2>(2000, 83), 30, 84));
  const auto sphere = gridfree::testing::MakeIcosphere(5);
  Soup<3> closed{ sphere.Vertices, sphere.Simplices };
  std::vector<Vec3> inside;
  for (int i = 0; i < 40; ++i)
  {
    inside.emplace_back(0.02 * i - 0.4, 0.3 - 0.01 * i, 0.015 * i - 0.3);
  }
  CheckHintedQueries<3>(closed, inside);
}

TEST(Bvh, DistanceLowerBound)
{
  CheckDistanceLowerBound<3>(MakeSoup<3>(3000, 71), MakeQueries(MakeSoup<3>(3000, 71), 60, 72));
  CheckDistanceLowerBound<2>(MakeSoup<2>(3000, 73), MakeQueries(MakeSoup<2>(3000, 73), 60, 74));
  // Deep inside a closed sphere, where relaxation matters most.
  const auto sphere = gridfree::testing::MakeIcosphere(5);
  Soup<3> closed{ sphere.Vertices, sphere.Simplices };
  std::mt19937_64 rng(75);
  std::uniform_real_distribution<double> u(-0.57, 0.57);
  std::vector<Vec3> inside;
  for (int i = 0; i < 400; ++i)
  {
    inside.emplace_back(u(rng), u(rng), u(rng));
  }
  inside.emplace_back(0.0, 0.0, 0.0);
  CheckDistanceLowerBound<3>(closed, inside);
}
} // namespace

// Ranges of 2^12 primitives or more build their subtrees as parallel tasks:
// the hierarchy must be the same whatever the thread count (same answers,
// same primitive, same size), valid, and exact.
TEST(Bvh, ParallelBuildIsTheSameOnAnyThreadCount)
{
  const auto mesh = gridfree::testing::MakeIcosphere(6); // 81,920 triangles
  ASSERT_GT(mesh.Simplices.size(), 2u << 15);
  Bvh<3> one, two;
  tbb::task_arena(1).execute([&] { one.Build(mesh.Vertices, mesh.Simplices); });
  tbb::task_arena(2).execute([&] { two.Build(mesh.Vertices, mesh.Simplices); });
  ASSERT_TRUE(one.Validate());
  ASSERT_TRUE(two.Validate());
  EXPECT_EQ(one.MemoryBytes(), two.MemoryBytes());
  Soup<3> soup{ mesh.Vertices, mesh.Simplices };
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int i = 0; i < 400; ++i)
  {
    const Vec3 x(u(rng), u(rng), u(rng));
    const auto a = one.ClosestPoint(x);
    const auto b = two.ClosestPoint(x);
    ASSERT_EQ(a.primitive, b.primitive);
    ASSERT_EQ(a.distance, b.distance);
    const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
    const auto ha = one.Intersect(x, d);
    const auto hb = two.Intersect(x, d);
    ASSERT_EQ(ha.primitive, hb.primitive);
    ASSERT_EQ(ha.t, hb.t);
    if (i < 20)
    {
      CheckQuery(two, soup, x, 2.0);
      ASSERT_FALSE(HasFatalFailure());
    }
  }
}

// The float leaf filter (BvhLeafFilter.h) skips a primitive only when it is
// proved farther than the radius asked about. Asking exactly at each
// primitive's true distance (and one ulp below it) must never skip it, which
// a bound without its rounding margins would break; asking at half the
// distance must skip nearly every proper primitive, or the filter is idle.
template <int DIM>
void CheckLeafFilter(std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 5);
  int proper = 0, skippedAtHalf = 0;
  for (int round = 0; round < 4000; ++round)
  {
    // A centre far from the origin and a scale from tiny to large, so that
    // the float copies' displacement matters.
    const double scale = std::pow(10.0, 6.0 * unit(rng));
    Vec<DIM> center;
    for (int k = 0; k < DIM; ++k)
    {
      center[k] = 1e3 * scale * unit(rng);
    }
    std::array<std::array<Vec<DIM>, DIM>, 4> prims;
    double largest = 0.0;
    for (auto& p : prims)
    {
      for (int v = 0; v < DIM; ++v)
      {
        for (int k = 0; k < DIM; ++k)
        {
          p[v][k] = center[k] + scale * unit(rng);
        }
      }
      switch (kind(rng))
      {
        case 0: // degenerate: all vertices equal
          for (int v = 1; v < DIM; ++v)
          {
            p[v] = p[0];
          }
          break;
        case 1: // degenerate: collinear (in 3D) or a point (in 2D)
          p[DIM - 1] = p[0] + 0.5 * (p[1] - p[0]);
          break;
        case 2: // tiny next to its distance
          for (int v = 1; v < DIM; ++v)
          {
            p[v] = p[0] + 1e-9 * (p[v] - p[0]);
          }
          break;
        default:
          break;
      }
      for (const auto& v : p)
      {
        largest = std::max(largest, (v - center).cwiseAbs().maxCoeff());
      }
    }
    const auto group = gridfree::testing::LeafGroupOf<DIM>(prims, center);
    Vec<DIM> x;
    for (int k = 0; k < DIM; ++k)
    {
      // Queries near, on and far from the primitives.
      x[k] = center[k] + scale * unit(rng) * std::pow(10.0, 2.0 * unit(rng) - 1.0);
    }
    if (round % 7 == 0)
    {
      x = prims[0][0] + 0.3 * (prims[0][1] - prims[0][0]); // on a primitive
    }
    if (round % 7 == 1 || round % 7 == 2)
    {
      // Just off a primitive's interior, far nearer than its size: the
      // margins then matter most (the dot products cancel, and the float
      // copies' displacement is large next to the distance).
      Vec<DIM> normal;
      if constexpr (DIM == 3)
      {
        normal = (prims[1][1] - prims[1][0]).cross(prims[1][2] - prims[1][0]);
      }
      else
      {
        normal = Vec2(prims[1][0][1] - prims[1][1][1], prims[1][1][0] - prims[1][0][0]);
      }
      Vec<DIM> inside = prims[1][0];
      for (int v = 1; v < DIM; ++v)
      {
        inside += (0.4 / DIM) * (prims[1][v] - prims[1][0]);
      }
      if (normal.norm() > 0.0)
      {
        x = inside + scale * std::pow(10.0, -7.0 * std::abs(unit(rng))) * normal.normalized();
      }
    }
    float q[DIM];
    double queryLargest = 0.0;
    for (int k = 0; k < DIM; ++k)
    {
      const double y = x[k] - center[k];
      q[k] = static_cast<float>(y);
      queryLargest = std::max(queryLargest, std::abs(y));
    }
    // The margins the hierarchy uses (Bvh.h): vertices and query.
    const double margin =
      (largest * (1.0 + 0x1p-40) + queryLargest) * 0x1p-23 * (1.0 + 0x1p-20);
    gridfree::detail::BvhLeafBounds bounds;
    gridfree::detail::LeafFilterBounds<DIM>(group, q, bounds);
    double d2[4];
    for (int lane = 0; lane < 4; ++lane)
    {
      if constexpr (DIM == 3)
      {
        d2[lane] = gridfree::SquaredDistanceToTriangle(x, prims[lane][0], prims[lane][1], prims[lane][2]);
      }
      else
      {
        d2[lane] = gridfree::SquaredDistanceToSegment<2>(x, prims[lane][0], prims[lane][1]);
      }
    }
    for (int lane = 0; lane < 4; ++lane)
    {
      for (const double r2 : { d2[lane], std::nextafter(d2[lane], 0.0) })
      {
        const int skip = gridfree::detail::LeafFilterSkipMask(bounds, gridfree::detail::LeafFilterRadius2(r2, margin));
        ASSERT_FALSE(skip >> lane & 1) << "lane " << lane << " skipped at its own distance "
                                       << std::sqrt(d2[lane]) << ", scale " << scale;
        for (int other = 0; other < 4; ++other)
        {
          if (skip >> other & 1)
          {
            ASSERT_GT(d2[other], r2) << "lane " << other << " skipped but nearer";
          }
        }
      }
      const double size = (prims[lane][1] - prims[lane][0]).norm();
      if (size > 1e-3 * scale && d2[lane] > 1e-6 * scale * scale)
      {
        ++proper;
        skippedAtHalf += gridfree::detail::LeafFilterSkipMask(bounds,
                           gridfree::detail::LeafFilterRadius2(0.25 * d2[lane], margin)) >> lane & 1;
      }
    }
  }
  ASSERT_GT(proper, 1000);
  EXPECT_GT(skippedAtHalf, 0.99 * proper);
}

TEST(Bvh, LeafFilterSkipsOnlyWhatIsProvedFarther)
{
  CheckLeafFilter<3>(71);
  CheckLeafFilter<2>(72);
}
