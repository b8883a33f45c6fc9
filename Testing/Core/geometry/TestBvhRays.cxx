// Tests of the BVH ray queries (Intersect, Occluded) and of their primitive
// tests.
//
// The hierarchy must return what a brute-force loop over all primitives with
// the same primitive test returns: its float box tests may never cut off a
// hit. The primitive tests are checked against an independent reference away
// from edges, and for watertightness on closed meshes: rays aimed exactly at
// vertices and edge midpoints never slip through. Seeds are fixed.
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/Bvh.h>
#include "TestMeshes.h"
#include <gridfree/math/Vector.h>

#include "RandomSoups.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{
using gridfree::Bvh;
using gridfree::testing::MakeSoup;
using gridfree::testing::Soup;
using gridfree::RayHit;
using gridfree::Vec;
using gridfree::Vec2;
using gridfree::Vec3;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

//------------------------------------------------------------------------------
// Brute-force reference: the same primitive test, over every primitive.
template <int DIM>
bool KernelHit(const Soup<DIM>& soup, std::size_t p, const Vec<DIM>& o, const Vec<DIM>& d,
  double tMin, double tMax, double& t, Vec<DIM>& w)
{
  const gridfree::detail::RayFrame<DIM> frame(o, d);
  Vec<DIM> v[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    v[k] = soup.Vertices[soup.Primitives[p][k]];
  }
  return frame.Intersect(v, tMin, tMax, t, w);
}

template <int DIM>
RayHit<DIM> BruteForce(
  const Soup<DIM>& soup, const Vec<DIM>& o, const Vec<DIM>& d, double tMax, double tMin)
{
  RayHit<DIM> best;
  for (std::size_t p = 0; p < soup.Primitives.size(); ++p)
  {
    double t;
    Vec<DIM> w;
    if (KernelHit(soup, p, o, d, tMin, tMax, t, w) && t < best.t)
    {
      best.t = t;
      best.primitive = static_cast<std::int64_t>(p);
      best.barycentric = w;
      best.point = o + t * d;
    }
  }
  return best;
}

/// Checks one ray of a BVH against brute force, for Intersect and Occluded.
template <int DIM>
void CheckRay(const Bvh<DIM>& bvh, const Soup<DIM>& soup, const Vec<DIM>& o,
  const Vec<DIM>& d, double tMax, double tMin)
{
  const RayHit<DIM> ref = BruteForce(soup, o, d, tMax, tMin);
  const RayHit<DIM> hit = bvh.Intersect(o, d, tMax, tMin);
  ASSERT_EQ(hit.Hit(), ref.Hit()) << "origin " << o.transpose() << " direction "
                                  << d.transpose() << " window " << tMin << " " << tMax;
  EXPECT_EQ(bvh.Occluded(o, d, tMax, tMin), ref.Hit());
  if (!ref.Hit())
  {
    EXPECT_EQ(hit.t, kInf);
    return;
  }
  EXPECT_NEAR(hit.t, ref.t, 1e-12 * std::abs(ref.t));
  EXPECT_GE(hit.t, tMin);
  EXPECT_LE(hit.t, tMax);
  ASSERT_GE(hit.primitive, 0);
  ASSERT_LT(hit.primitive, static_cast<std::int64_t>(soup.Primitives.size()));
  // Up to ties, the reported primitive (an ORIGINAL index) is a nearest one:
  // its own test gives the reported t and weights.
  double t;
  Vec<DIM> w;
  ASSERT_TRUE(KernelHit(soup, static_cast<std::size_t>(hit.primitive), o, d, tMin, tMax, t, w));
  EXPECT_EQ(t, hit.t);
  EXPECT_EQ(w, hit.barycentric);
  EXPECT_EQ(hit.point, Vec<DIM>(o + hit.t * d));
}

/// Random rays for a soup: origins inside the box, on primitives and far
/// away; directions random, towards a point of a primitive (a vertex
/// included), or with components exactly 0, -0 or tiny; lengths from 1e-30
/// to 1e30; windows [0, inf) or random.
template <int DIM>
void CheckRandomRays(const Bvh<DIM>& bvh, const Soup<DIM>& soup, int count, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss;
  gridfree::BoundingBox<DIM> box;
  for (const auto& v : soup.Vertices)
  {
    box.Expand(v);
  }
  const double diag = std::max(box.Diagonal(), 1e-300);
  auto unit = [&]()
  {
    Vec<DIM> d;
    for (int k = 0; k < DIM; ++k)
    {
      d[k] = gauss(rng);
    }
    return Vec<DIM>(d.normalized());
  };
  auto pointOn = [&]()
  {
    const auto& prim = soup.Primitives[rng() % soup.Primitives.size()];
    if (rng() % 3 == 0)
    {
      return Vec<DIM>(soup.Vertices[prim[rng() % DIM]]);
    }
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
    return p;
  };
  for (int i = 0; i < count; ++i)
  {
    Vec<DIM> o;
    switch (i % 3)
    {
      case 0:
        for (int k = 0; k < DIM; ++k)
        {
          o[k] = box.Min[k] + (box.Max[k] - box.Min[k]) * (1.2 * u01(rng) - 0.1);
        }
        break;
      case 1:
        o = pointOn() + diag * std::pow(10.0, -12.0 + 11.0 * u01(rng)) * unit();
        break;
      default:
        o = box.Center() + diag * std::pow(10.0, 8.0 * u01(rng)) * unit();
        break;
    }
    Vec<DIM> d = (i % 2) ? Vec<DIM>(pointOn() - o) : unit();
    if (i % 7 == 0)
    {
      const int k = static_cast<int>(rng() % DIM);
      const int mode = static_cast<int>(rng() % 3);
      d[k] = mode == 0 ? 0.0 : (mode == 1 ? -0.0 : 1e-300);
      if (d.cwiseAbs().maxCoeff() == 0.0)
      {
        d[(k + 1) % DIM] = 1.0;
      }
    }
    if (i % 5 == 0)
    {
      d *= std::pow(10.0, -30.0 + 60.0 * u01(rng));
    }
    double tMax = kInf;
    double tMin = 0.0;
    if (i % 4 == 3)
    {
      const RayHit<DIM> full = BruteForce(soup, o, d, kInf, 0.0);
      const double scale = full.Hit() ? full.t : diag / d.norm();
      tMin = scale * (2.0 * u01(rng) - 0.5);
      tMax = tMin + scale * u01(rng);
    }
    CheckRay(bvh, soup, o, d, tMax, tMin);
    if (::testing::Test::HasFatalFailure())
    {
      return;
    }
  }
}

template <int DIM>
void CheckSoup(Soup<DIM> soup, int rays, std::uint64_t seed)
{
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  CheckRandomRays(bvh, soup, rays, seed);
}

template <int DIM>
Soup<DIM> Transformed(Soup<DIM> soup, double scale, double offset)
{
  for (auto& v : soup.Vertices)
  {
    v = scale * v + Vec<DIM>::Constant(offset);
  }
  return soup;
}

//------------------------------------------------------------------------------
// The leaf filter for rays (BvhLeafFilter.h), set up as the hierarchy sets it
// up: groups of four primitives (random, degenerate or tiny, at scales from
// 1e-6 to 1e6, offset from the origin) and rays aimed at a primitive's
// vertex, edge or interior, or just beside an edge (down to 1e-9 of its
// size), from near and far. A skipped primitive must be one the exact test
// misses, and nearly all primitives a ray clearly misses must be skipped.
template <int DIM>
void CheckRayLeafFilter(std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss;
  auto unit = [&]()
  {
    Vec<DIM> d;
    for (int k = 0; k < DIM; ++k)
    {
      d[k] = gauss(rng);
    }
    return Vec<DIM>(d.normalized());
  };
  int clearMisses = 0, clearSkipped = 0, hits = 0;
  for (int round = 0; round < 40000; ++round)
  {
    const double scale = std::pow(10.0, 12.0 * u01(rng) - 6.0);
    const Vec<DIM> center = (round % 3 == 0) ? Vec<DIM>(scale * 1e4 * unit()) : Vec<DIM>::Zero();
    Vec<DIM> prims[4][DIM];
    for (auto& prim : prims)
    {
      const Vec<DIM> base = center + scale * unit();
      const double size = (round % 5 == 0) ? 1e-4 * scale : scale;
      for (auto& v : prim)
      {
        v = base + size * unit();
      }
      if (round % 11 == 0)
      {
        prim[1] = prim[0]; // degenerate
      }
    }
    double largest = 0.0;
    for (const auto& prim : prims)
    {
      for (const auto& v : prim)
      {
        largest = std::max(largest, (v - center).cwiseAbs().maxCoeff());
      }
    }
    const auto group = gridfree::testing::LeafGroupOf<DIM>(prims, center);
    const double vertexMargin = largest * 0x1p-23 * (1.0 + 0x1p-20); // as Bvh.h

    // The target: a point of lane 0's primitive or just beside one of its
    // edges, in its plane (3D) or on its line (2D).
    const Vec<DIM>(&t)[DIM] = prims[0];
    const int edge = static_cast<int>(rng() % DIM);
    const Vec<DIM> a = t[edge], b = t[(edge + 1) % DIM];
    const int kind = round % 4;
    Vec<DIM> target = kind == 0 ? a : Vec<DIM>(a + u01(rng) * (b - a));
    if (kind == 1 && DIM == 3)
    {
      target += 0.5 * u01(rng) * (t[(edge + 2) % DIM] - target); // interior
    }
    double beside = 0.0;
    if (kind == 3)
    {
      // Outward from the edge, within the primitive's plane or line.
      Vec<DIM> out;
      if constexpr (DIM == 3)
      {
        const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
        out = (b - a).cross(normal);
        if (out.dot(t[(edge + 2) % 3] - a) > 0.0)
        {
          out = -out;
        }
      }
      else
      {
        out = (edge == 0 ? a - b : b - a); // beyond an end of the segment
        target = edge == 0 ? a : b;
      }
      if (out.norm() > 0.0)
      {
        beside = (b - a).norm() * std::pow(10.0, -9.0 * u01(rng));
        target += beside * out.normalized();
      }
    }
    const Vec<DIM> d = unit() * std::pow(10.0, 4.0 * u01(rng) - 2.0);
    const Vec<DIM> o = target - std::pow(10.0, 8.0 * u01(rng) - 3.0) * scale / d.norm() * d;

    const gridfree::detail::RayFrame<DIM> frame(o, d);
    int axis[DIM - 1];
    double shear[DIM - 1];
    frame.Projection(axis, shear);
    double y[DIM], err[DIM], originOffset = 0.0;
    for (int k = 0; k < DIM; ++k)
    {
      y[k] = o[k] - center[k];
      err[k] = std::abs(y[k]) * 0x1p-52;
      originOffset = std::max(originOffset, std::abs(y[k]));
    }
    gridfree::detail::LeafRayProjection<DIM> projection;
    const float r2 = gridfree::detail::LeafRayFilterSetup<DIM>(
      y, err, axis, frame.Kz, shear, vertexMargin, originOffset, projection);
    gridfree::detail::BvhLeafBounds bounds;
    gridfree::detail::LeafFilterRayBounds<DIM>(group, projection, bounds);
    const int skip = gridfree::detail::LeafFilterSkipMask(bounds, r2);

    for (int lane = 0; lane < 4; ++lane)
    {
      double tHit;
      Vec<DIM> w;
      const bool hit = frame.Intersect(prims[lane], -kInf, kInf, tHit, w);
      hits += hit;
      ASSERT_FALSE(hit && (skip >> lane & 1))
        << "lane " << lane << " skipped but hit, round " << round << ", scale " << scale
        << ", beside " << beside;
    }
    // Clearly beside (1e-3 of the edge or more, origin not far): skipped.
    const bool regular = (round % 11 != 0) && (round % 5 != 0);
    if (regular && beside > 1e-3 * (b - a).norm() && (o - target).norm() < 1e2 * scale)
    {
      ++clearMisses;
      clearSkipped += skip & 1;
    }
  }
  EXPECT_GT(hits, 5000); // the aimed rays do hit: the check above is not vacuous
  ASSERT_GT(clearMisses, 1000);
  EXPECT_GT(clearSkipped, 0.98 * clearMisses) << clearSkipped << " of " << clearMisses;
}

TEST(BvhRays, LeafFilterSkipsOnlyMisses)
{
  CheckRayLeafFilter<3>(81);
  CheckRayLeafFilter<2>(82);
}

//------------------------------------------------------------------------------
// Independent reference for the triangle test: Moller-Trumbore in long double,
// used only for rays far from the triangle's edges.
bool ReferenceTriangleHit(const Vec3& o, const Vec3& d, const Vec3 (&v)[3], long double& t,
  long double (&w)[3])
{
  using L = long double;
  L e1[3], e2[3], s[3], dd[3];
  for (int k = 0; k < 3; ++k)
  {
    e1[k] = L(v[1][k]) - L(v[0][k]);
    e2[k] = L(v[2][k]) - L(v[0][k]);
    s[k] = L(o[k]) - L(v[0][k]);
    dd[k] = d[k];
  }
  auto cross = [](const L* a, const L* b, L* c)
  {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const L* a, const L* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  L p[3], q[3];
  cross(dd, e2, p);
  const L det = dot(e1, p);
  cross(s, e1, q);
  w[1] = dot(s, p) / det;
  w[2] = dot(dd, q) / det;
  w[0] = 1 - w[1] - w[2];
  t = dot(e2, q) / det;
  return w[0] >= 0 && w[1] >= 0 && w[2] >= 0;
}

//------------------------------------------------------------------------------
TEST(RayPrimitives, TriangleKnownHit)
{
  const Vec3 v[3] = { Vec3(0, 0, 2), Vec3(4, 0, 2), Vec3(0, 4, 2) };
  const gridfree::detail::RayFrame<3> frame(Vec3(1, 1, 0), Vec3(0, 0, 0.5));
  double t;
  Vec3 w;
  ASSERT_TRUE(frame.Intersect(v, 0.0, kInf, t, w));
  EXPECT_EQ(t, 4.0);
  EXPECT_NEAR(w[0], 0.5, 1e-15);
  EXPECT_NEAR(w[1], 0.25, 1e-15);
  EXPECT_NEAR(w[2], 0.25, 1e-15);
  // Both orientations, both directions of travel.
  const Vec3 flipped[3] = { v[0], v[2], v[1] };
  EXPECT_TRUE(frame.Intersect(flipped, 0.0, kInf, t, w));
  const gridfree::detail::RayFrame<3> back(Vec3(1, 1, 5), Vec3(0, 0, -1));
  EXPECT_TRUE(back.Intersect(v, 0.0, kInf, t, w));
  EXPECT_EQ(t, 3.0);
  // Window ends are inclusive.
  EXPECT_TRUE(back.Intersect(v, 3.0, 3.0, t, w));
  EXPECT_FALSE(back.Intersect(v, 0.0, std::nextafter(3.0, 0.0), t, w));
  EXPECT_FALSE(back.Intersect(v, std::nextafter(3.0, 4.0), kInf, t, w));
  // Behind the origin.
  EXPECT_FALSE(back.Intersect(v, 0.0, kInf, t, w) && t < 0.0);
  const gridfree::detail::RayFrame<3> away(Vec3(1, 1, 5), Vec3(0, 0, 1));
  EXPECT_FALSE(away.Intersect(v, 0.0, kInf, t, w));
  EXPECT_TRUE(away.Intersect(v, -kInf, kInf, t, w));
  EXPECT_EQ(t, -3.0);
}

TEST(RayPrimitives, ParallelAndDegenerateTrianglesNeverHit)
{
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&]() { return Vec3(u(rng), u(rng), u(rng)); };
  double t;
  Vec3 w;
  for (int i = 0; i < 20000; ++i)
  {
    const Vec3 a = point();
    const Vec3 b = point();
    const Vec3 c = point();
    // A ray parallel to the triangle, above it, and one in its plane through
    // a point of it (coplanar grazing).
    const Vec3 along = (i % 3 == 0) ? Vec3(b - a) : Vec3(c - b);
    Vec3 v[3] = { a, b, c };
    if (i % 2)
    {
      // An axis-aligned plane keeps the coplanar ray exactly in the plane.
      for (Vec3& p : v)
      {
        p[i % 3] = 0.5;
      }
    }
    const Vec3 n = (v[1] - v[0]).cross(v[2] - v[0]);
    const Vec3 mid = (v[0] + 2.0 * v[1] + v[2]) / 4.0;
    const Vec3 dir = (i % 2) ? Vec3(v[(i / 2) % 3] - mid) : along;
    const gridfree::detail::RayFrame<3> above(mid + 0.01 * n, dir);
    EXPECT_FALSE(above.Intersect(v, -kInf, kInf, t, w)) << i;
    if (i % 2)
    {
      const gridfree::detail::RayFrame<3> inPlane(mid - dir, dir);
      EXPECT_FALSE(inPlane.Intersect(v, -kInf, kInf, t, w)) << i;
    }

    // Zero-area triangles: repeated vertex, identical vertices, exactly
    // collinear ones (axis aligned, and with power-of-two steps), for rays
    // aimed at their vertices and midpoints.
    const double step = std::ldexp(1.0, static_cast<int>(rng() % 20) - 10);
    const Vec3 axis = Vec3::Unit(rng() % 3) * step;
    const Vec3 diagonal = Vec3(1, -2, 4) * step;
    const Vec3 g = (a * 1024.0).array().round() / 1024.0; // sums below are exact
    const Vec3 degenerate[5][3] = { { a, a, b }, { a, b, b }, { a, a, a },
      { a, Vec3(a + axis), Vec3(a + 3.0 * axis) },
      { Vec3(g + 2.0 * diagonal), g, Vec3(g + diagonal) } };
    const Vec3 o = 3.0 * point();
    for (const auto& tri : degenerate)
    {
      for (const Vec3& target : { tri[0], tri[1], tri[2], Vec3(0.5 * (tri[0] + tri[2])) })
      {
        const gridfree::detail::RayFrame<3> frame(o, target - o);
        EXPECT_FALSE(frame.Intersect(tri, -kInf, kInf, t, w)) << i;
      }
    }
  }
}

TEST(RayPrimitives, TriangleMatchesReferenceAwayFromEdges)
{
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&]() { return Vec3(u(rng), u(rng), u(rng)); };
  int hits = 0;
  for (int i = 0; i < 100000; ++i)
  {
    const double scale = std::pow(10.0, 10.0 * u(rng));
    const Vec3 shift = point() * scale * 100.0 * (i % 2);
    const Vec3 v[3] = { Vec3(scale * point() + shift), Vec3(scale * point() + shift),
      Vec3(scale * point() + shift) };
    const Vec3 o = 3.0 * scale * point() + shift;
    const Vec3 d = Vec3(0.5 * scale * point() + shift - o) * std::pow(10.0, 5.0 * u(rng));
    long double tRef, wRef[3];
    const bool ref = ReferenceTriangleHit(o, d, v, tRef, wRef);
    const long double margin = *std::min_element(wRef, wRef + 3);
    const long double outside = -margin;
    const gridfree::detail::RayFrame<3> frame(o, d);
    double t;
    Vec3 w;
    const bool hit = frame.Intersect(v, -kInf, kInf, t, w);
    if (ref && margin > 1e-6)
    {
      ASSERT_TRUE(hit) << i;
      EXPECT_NEAR(t, static_cast<double>(tRef), 1e-12 * std::abs(static_cast<double>(tRef)));
      for (int k = 0; k < 3; ++k)
      {
        EXPECT_NEAR(w[k], static_cast<double>(wRef[k]), 1e-10);
      }
      EXPECT_NEAR(w.sum(), 1.0, 1e-15);
      ++hits;
    }
    else if (!ref && outside > 1e-6)
    {
      ASSERT_FALSE(hit) << i;
    }
  }
  EXPECT_GT(hits, 5000);
}

TEST(RayPrimitives, Segments)
{
  const Vec2 v[2] = { Vec2(2, -1), Vec2(2, 3) };
  double t;
  Vec2 w;
  const gridfree::detail::RayFrame<2> frame(Vec2(0, 0), Vec2(0.5, 0));
  ASSERT_TRUE(frame.Intersect(v, 0.0, kInf, t, w));
  EXPECT_EQ(t, 4.0);
  EXPECT_EQ(w, Vec2(0.75, 0.25));
  EXPECT_FALSE(frame.Intersect(v, 0.0, 3.9, t, w));
  EXPECT_FALSE(frame.Intersect(v, 4.1, kInf, t, w));
  // Through an end point: hit, with all the weight on that end.
  const gridfree::detail::RayFrame<2> toEnd(Vec2(0, 1), Vec2(1, 1));
  ASSERT_TRUE(toEnd.Intersect(v, 0.0, kInf, t, w));
  EXPECT_EQ(t, 2.0);
  EXPECT_EQ(w, Vec2(0.0, 1.0));
  // Along the segment's line, degenerate segments: no hit.
  const gridfree::detail::RayFrame<2> along(Vec2(2, -5), Vec2(0, 1));
  EXPECT_FALSE(along.Intersect(v, -kInf, kInf, t, w));
  const Vec2 point[2] = { Vec2(1, 1), Vec2(1, 1) };
  const gridfree::detail::RayFrame<2> toPoint(Vec2(0.3, -0.7), Vec2(0.7, 1.7));
  EXPECT_FALSE(toPoint.Intersect(point, -kInf, kInf, t, w));

  // Random segments against a long double reference away from the ends.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 100000; ++i)
  {
    const double scale = std::pow(10.0, 10.0 * u(rng));
    const Vec2 s[2] = { Vec2(u(rng), u(rng)) * scale, Vec2(u(rng), u(rng)) * scale };
    const Vec2 o = Vec2(u(rng), u(rng)) * 3.0 * scale;
    const Vec2 d = Vec2(Vec2(u(rng), u(rng)) * scale - o) * std::pow(10.0, 5.0 * u(rng));
    using L = long double;
    const L ex = L(s[1][0]) - s[0][0], ey = L(s[1][1]) - s[0][1];
    const L px = L(s[0][0]) - o[0], py = L(s[0][1]) - o[1];
    const L den = L(d[0]) * ey - L(d[1]) * ex;
    const L tRef = (px * ey - py * ex) / den;
    const L a = (px * d[1] - py * d[0]) / den; // position along the segment
    const gridfree::detail::RayFrame<2> f(o, d);
    const bool hit = f.Intersect(s, -kInf, kInf, t, w);
    if (a > 1e-6 && a < 1 - 1e-6)
    {
      ASSERT_TRUE(hit) << i;
      EXPECT_NEAR(t, static_cast<double>(tRef), 1e-12 * std::abs(static_cast<double>(tRef)));
      EXPECT_NEAR(w[1], static_cast<double>(a), 1e-10);
      ++hits;
    }
    else if (a < -1e-6 || a > 1 + 1e-6)
    {
      ASSERT_FALSE(hit) << i;
    }
  }
  EXPECT_GT(hits, 10000);
}

//------------------------------------------------------------------------------
TEST(BvhRays, EmptyAndInvalidInput)
{
  Bvh<3> empty;
  EXPECT_FALSE(empty.Intersect(Vec3(0, 0, 0), Vec3(1, 0, 0)).Hit());
  EXPECT_FALSE(empty.Occluded(Vec3(0, 0, 0), Vec3(1, 0, 0)));

  const auto mesh = gridfree::testing::MakeIcosphere(2);
  Bvh<3> bvh;
  bvh.Build(mesh.Vertices, mesh.Simplices);
  const Vec3 o(0.1, 0.2, 0.3);
  const Vec3 d(1, 2, 3);
  ASSERT_TRUE(bvh.Intersect(o, d).Hit());
  const Vec3 bad[] = { Vec3(kNaN, 0, 0), Vec3(0, kInf, 0), Vec3(0, 0, -kInf) };
  for (const Vec3& b : bad)
  {
    EXPECT_FALSE(bvh.Intersect(b, d).Hit());
    EXPECT_FALSE(bvh.Intersect(o, b).Hit());
    EXPECT_FALSE(bvh.Occluded(b, d));
    EXPECT_FALSE(bvh.Occluded(o, b));
  }
  EXPECT_FALSE(bvh.Intersect(o, Vec3(0, 0, 0)).Hit());
  EXPECT_FALSE(bvh.Intersect(o, Vec3(-0.0, 0, -0.0)).Hit());
  EXPECT_FALSE(bvh.Occluded(o, Vec3(0, 0, 0)));
  // Empty or invalid windows.
  EXPECT_FALSE(bvh.Intersect(o, d, 1.0, 2.0).Hit());
  EXPECT_FALSE(bvh.Intersect(o, d, kNaN).Hit());
  EXPECT_FALSE(bvh.Intersect(o, d, kInf, kNaN).Hit());
  EXPECT_FALSE(bvh.Intersect(o, d, kInf, kInf).Hit());
  EXPECT_FALSE(bvh.Intersect(o, d, -kInf, -kInf).Hit());
  EXPECT_FALSE(bvh.Occluded(o, d, 1.0, 2.0));
  const RayHit<3> miss = bvh.Intersect(o, d, 1e-3);
  EXPECT_FALSE(miss.Hit());
  EXPECT_EQ(miss.t, kInf);
  EXPECT_EQ(miss.primitive, -1);
  // A window that takes the whole line finds the hit behind the origin.
  const RayHit<3> behind = bvh.Intersect(o, -d, 0.0, -kInf);
  ASSERT_TRUE(behind.Hit());
  EXPECT_LT(behind.t, 0.0);
  EXPECT_NEAR(behind.t, -bvh.Intersect(o, d).t, 0.02);
}

TEST(BvhRays, OnlyDegeneratePrimitives)
{
  Soup<3> soup;
  soup.Vertices = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0) };
  soup.Primitives = { { 0, 1, 2 }, { 0, 0, 3 }, { 3, 3, 3 }, { 1, 3, 1 } };
  Bvh<3> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 2000; ++i)
  {
    const Vec3 o(u(rng), u(rng), u(rng));
    const Vec3 target = (i % 2) ? soup.Vertices[i % 4] : Vec3(u(rng), u(rng), 0.0);
    EXPECT_FALSE(bvh.Intersect(o, target - o).Hit());
    EXPECT_FALSE(bvh.Occluded(o, target - o, kInf, -kInf));
  }
  Soup<2> soup2;
  soup2.Vertices = { Vec2(0, 0), Vec2(0, 0), Vec2(1, 1) };
  soup2.Primitives = { { 0, 1 }, { 2, 2 } };
  Bvh<2> bvh2;
  bvh2.Build(soup2.Vertices, soup2.Primitives);
  for (int i = 0; i < 2000; ++i)
  {
    const Vec2 o(u(rng), u(rng));
    EXPECT_FALSE(bvh2.Intersect(o, soup2.Vertices[i % 3] - o).Hit());
  }
}

TEST(BvhRays, TriangleSoupsMatchBruteForce)
{
  std::uint64_t seed = 100;
  for (const int n : { 1, 2, 7, 1000, 20000 })
  {
    SCOPED_TRACE(n);
    CheckSoup<3>(MakeSoup<3>(n, seed), n < 1000 ? 500 : 300, seed + 1);
    seed += 2;
  }
}

TEST(BvhRays, SegmentSoupsMatchBruteForce)
{
  std::uint64_t seed = 200;
  for (const int n : { 1, 2, 7, 1000, 20000 })
  {
    SCOPED_TRACE(n);
    CheckSoup<2>(MakeSoup<2>(n, seed), n < 1000 ? 500 : 300, seed + 1);
    seed += 2;
  }
}

TEST(BvhRays, HugeTinyAndOffsetCoordinates)
{
  const Soup<3> soup = MakeSoup<3>(3000, 300);
  for (const auto& [scale, offset] : { std::pair<double, double>{ 1e15, 0.0 }, { 1e-15, 0.0 },
         { 1e-150, 0.0 }, { 1.0, 1e6 }, { 1e-3, -3e7 }, { 1e12, 1e16 } })
  {
    SCOPED_TRACE(scale);
    SCOPED_TRACE(offset);
    CheckSoup<3>(Transformed(soup, scale, offset), 300, 301);
  }
  const Soup<2> soup2 = MakeSoup<2>(3000, 302);
  for (const auto& [scale, offset] :
    { std::pair<double, double>{ 1e15, 0.0 }, { 1e-15, 0.0 }, { 1.0, -4e7 } })
  {
    CheckSoup<2>(Transformed(soup2, scale, offset), 300, 303);
  }
}

TEST(BvhRays, CoplanarOverlapsAndTies)
{
  // Overlapping triangles in one plane (z = 0.25) and in a tilted plane,
  // duplicates of identical triangles, and a stack of parallel planes with
  // many triangles at exactly the same distance along axis-aligned rays.
  std::mt19937_64 rng(400);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Soup<3> soup;
  auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c)
  {
    const auto base = static_cast<std::int64_t>(soup.Vertices.size());
    soup.Vertices.insert(soup.Vertices.end(), { a, b, c });
    soup.Primitives.push_back({ base, base + 1, base + 2 });
  };
  for (int i = 0; i < 1500; ++i)
  {
    const Vec3 a(u(rng), u(rng), 0.25);
    add(a, Vec3(u(rng), u(rng), 0.25), Vec3(u(rng), u(rng), 0.25));
    const double x = u(rng), y = u(rng);
    auto tilted = [&](double px, double py) { return Vec3(px, py, 0.5 + 0.3 * px - 0.2 * py); };
    add(tilted(x, y), tilted(u(rng), u(rng)), tilted(u(rng), u(rng)));
  }
  for (int i = 0; i < 200; ++i)
  {
    add(Vec3(0, 0, 0.75), Vec3(1, 0, 0.75), Vec3(0, 1, 0.75)); // identical
  }
  for (int layer = 0; layer < 8; ++layer)
  {
    for (int i = 0; i < 16; ++i)
    {
      for (int j = 0; j < 16; ++j)
      {
        const double z = 1.0 + layer / 8.0;
        const Vec3 a(i / 16.0, j / 16.0, z);
        add(a, Vec3(a + Vec3(1.0 / 16, 0, 0)), Vec3(a + Vec3(0, 1.0 / 16, 0)));
        add(Vec3(a + Vec3(1.0 / 16, 1.0 / 16, 0)), Vec3(a + Vec3(0, 1.0 / 16, 0)),
          Vec3(a + Vec3(1.0 / 16, 0, 0)));
      }
    }
  }
  Bvh<3> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  CheckRandomRays(bvh, soup, 1000, 401);
  for (int i = 0; i < 1000; ++i)
  {
    // Vertical rays, up and down, some through the grid's vertices and edges.
    Vec3 o(u(rng), u(rng), (i % 2) ? -1.0 : 3.0);
    if (i % 3 == 0)
    {
      o.x() = std::floor(16 * o.x()) / 16;
    }
    if (i % 5 == 0)
    {
      o.y() = std::floor(16 * o.y()) / 16;
    }
    const Vec3 d(0, 0, (i % 2) ? 1.0 : -1.0);
    CheckRay(bvh, soup, o, d, kInf, 0.0);
    ASSERT_FALSE(HasFatalFailure());
    // Inside the grid, up and down rays always hit a layer.
    if (o.x() < 1 && o.y() < 1)
    {
      EXPECT_TRUE(bvh.Intersect(Vec3(o.x(), o.y(), 1.1), d).Hit()) << o.transpose();
    }
  }
}

TEST(BvhRays, TightClustersHitAtBoxCorners)
{
  // Clusters of tiny primitives (down to 1e-12 across) spread over
  // [-1000, 1000], with vertices on a power-of-two grid so that box faces
  // fall exactly on float values; rays aimed exactly at vertices (box corners
  // and faces) from near and far stress the conservative slab test.
  std::mt19937_64 rng(450);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Soup<3> soup;
  for (int cluster = 0; cluster < 300; ++cluster)
  {
    const Vec3 center = (1000.0 * Vec3(u(rng), u(rng), u(rng))).array().round();
    const double size = std::ldexp(1.0, -10 - static_cast<int>(rng() % 30));
    for (int i = 0; i < 10; ++i)
    {
      typename Bvh<3>::Primitive prim;
      for (int k = 0; k < 3; ++k)
      {
        const Vec3 offset = (8.0 * Vec3(u(rng), u(rng), u(rng))).array().round();
        soup.Vertices.push_back(center + size * offset);
        prim[k] = static_cast<std::int64_t>(soup.Vertices.size()) - 1;
      }
      soup.Primitives.push_back(prim);
    }
  }
  Bvh<3> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  for (int i = 0; i < 3000; ++i)
  {
    const Vec3& target = soup.Vertices[rng() % soup.Vertices.size()];
    const double reach = std::pow(10.0, -9.0 + 13.0 * (0.5 + 0.5 * u(rng)));
    Vec3 d(u(rng), u(rng), u(rng));
    if (i % 3 == 0)
    {
      d[i % 3 + (i % 2)] = 0.0; // in a box face plane
    }
    const Vec3 o = target - reach * d;
    CheckRay(bvh, soup, o, Vec3(target - o), kInf, 0.0);
    ASSERT_FALSE(HasFatalFailure());
  }
}

//------------------------------------------------------------------------------
// Watertightness on closed meshes.
double SphereExit(const Vec3& o, const Vec3& u, double radius)
{
  const double b = o.dot(u);
  return -b + std::sqrt(b * b - o.squaredNorm() + radius * radius);
}

TEST(BvhRays, ClosedIcosphere)
{
  const auto mesh = gridfree::testing::MakeIcosphere(5);
  Soup<3> soup{ mesh.Vertices, mesh.Simplices };
  Bvh<3> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  // The mesh lies between the unit sphere and its inscribed sphere.
  double inner = 1.0;
  for (const auto& f : mesh.Simplices)
  {
    const Vec3& a = mesh.Vertices[f[0]];
    const Vec3 n = (mesh.Vertices[f[1]] - a).cross(mesh.Vertices[f[2]] - a).normalized();
    inner = std::min(inner, std::abs(n.dot(a)));
  }
  std::mt19937_64 rng(500);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto unit = [&]() { return Vec3(Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized()); };
  auto interior = [&]() { return Vec3(inner * std::cbrt(u01(rng)) * 0.999 * unit()); };

  // Random rays from inside: exactly one crossing, at the tessellated sphere.
  for (int i = 0; i < 3000; ++i)
  {
    const Vec3 o = (i == 0) ? Vec3::Zero() : interior();
    const Vec3 u = unit();
    const double length = std::pow(10.0, 6.0 * u01(rng) - 3.0);
    const RayHit<3> hit = bvh.Intersect(o, length * u);
    ASSERT_TRUE(hit.Hit()) << i;
    EXPECT_GE(hit.t * length, SphereExit(o, u, inner) * (1 - 1e-12));
    EXPECT_LE(hit.t * length, SphereExit(o, u, 1.0) * (1 + 1e-12));
    EXPECT_TRUE(bvh.Occluded(o, length * u));
    if (i < 300)
    {
      CheckRay(bvh, soup, o, Vec3(length * u), kInf, 0.0);
      int crossings = 0;
      for (std::size_t p = 0; p < soup.Primitives.size(); ++p)
      {
        double t;
        Vec3 w;
        if (KernelHit(soup, p, o, Vec3(length * u), 0.0, kInf, t, w))
        {
          EXPECT_NEAR(t, hit.t, 1e-12 * hit.t); // several only at a shared edge
          ++crossings;
        }
      }
      EXPECT_GE(crossings, 1);
    }
  }

  // Rays aimed exactly at vertices and edge midpoints, from inside and from
  // outside (on the side the target faces, so that the ray is not tangent to
  // the mesh there): no ray slips through.
  for (int i = 0; i < 20000; ++i)
  {
    const auto& f = mesh.Simplices[rng() % mesh.Simplices.size()];
    const int k = static_cast<int>(rng() % 3);
    const Vec3 target = (i % 2) ? mesh.Vertices[f[k]]
                                : Vec3(0.5 * (mesh.Vertices[f[k]] + mesh.Vertices[f[(k + 1) % 3]]));
    Vec3 o = interior();
    if (i % 4 >= 2)
    {
      do
      {
        o = 3.0 * unit();
      } while ((o - target).normalized().dot(target.normalized()) < 0.2);
    }
    const Vec3 d = target - o;
    const RayHit<3> hit = bvh.Intersect(o, d);
    ASSERT_TRUE(hit.Hit()) << i;
    if (i % 4 < 2)
    {
      EXPECT_NEAR(hit.t, 1.0, 1e-12) << i;
    }
    else
    {
      EXPECT_LE(hit.t, 1.0 + 1e-12) << i; // may enter elsewhere first
    }
    EXPECT_TRUE(bvh.Occluded(o, d, 1.0 + 1e-9));
    // From inside, the window just before the target sees nothing.
    if (i % 4 < 2)
    {
      EXPECT_FALSE(bvh.Occluded(o, d, 1.0 - 1e-9)) << i;
    }
  }
}

TEST(BvhRays, ClosedCube)
{
  // Axis-aligned faces: rays through the cube's grid vertices, edges and
  // corners, with zero direction components.
  const auto mesh = gridfree::testing::MakeCube(8);
  Bvh<3> bvh;
  bvh.Build(mesh.Vertices, mesh.Simplices);
  std::mt19937_64 rng(600);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  for (int i = 0; i < 5000; ++i)
  {
    const Vec3 o(u(rng), u(rng), u(rng));
    const Vec3& target = mesh.Vertices[rng() % mesh.Vertices.size()];
    Vec3 d = target - o;
    const RayHit<3> hit = bvh.Intersect(o, d);
    ASSERT_TRUE(hit.Hit()) << i;
    EXPECT_NEAR(hit.t, 1.0, 1e-12);
    // Axis-aligned rays through grid lines.
    Vec3 g = o;
    g[i % 3] = std::round(4.0 * g[i % 3]) / 4.0;
    g[(i + 1) % 3] = std::round(4.0 * g[(i + 1) % 3]) / 4.0;
    d = Vec3::Zero();
    d[(i + 2) % 3] = (i % 2) ? 1.0 : -1.0;
    const RayHit<3> axial = bvh.Intersect(g, d);
    ASSERT_TRUE(axial.Hit()) << i;
    EXPECT_NEAR(axial.t, 1.0 - d[(i + 2) % 3] * g[(i + 2) % 3], 1e-15);
  }
}

TEST(BvhRays, ClosedPolygon)
{
  const auto mesh = gridfree::testing::MakeCircle(1000);
  Soup<2> soup{ mesh.Vertices, mesh.Simplices };
  Bvh<2> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_TRUE(bvh.Validate());
  const double inner = std::cos(M_PI / 1000);
  std::mt19937_64 rng(700);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto unit = [&]()
  {
    const double a = 2.0 * M_PI * u01(rng);
    return Vec2(std::cos(a), std::sin(a));
  };
  for (int i = 0; i < 20000; ++i)
  {
    const Vec2 o = inner * 0.999 * std::sqrt(u01(rng)) * unit();
    const Vec2 u = unit();
    const RayHit<2> hit = bvh.Intersect(o, u);
    ASSERT_TRUE(hit.Hit()) << i;
    const double b = o.dot(u);
    EXPECT_GE(hit.t, (-b + std::sqrt(b * b - o.squaredNorm() + inner * inner)) * (1 - 1e-12));
    EXPECT_LE(hit.t, (-b + std::sqrt(b * b - o.squaredNorm() + 1.0)) * (1 + 1e-12));
    // Through a vertex, from inside and outside.
    const Vec2& v = mesh.Vertices[rng() % mesh.Vertices.size()];
    const RayHit<2> through = bvh.Intersect(o, v - o);
    ASSERT_TRUE(through.Hit()) << i;
    EXPECT_NEAR(through.t, 1.0, 1e-12);
    EXPECT_FALSE(bvh.Occluded(o, v - o, 1.0 - 1e-9));
    const Vec2 far = 2.0 * unit();
    EXPECT_TRUE(bvh.Intersect(far, v - far).Hit()) << i;
    if (i < 300)
    {
      CheckRay(bvh, soup, o, u, kInf, 0.0);
      CheckRay(bvh, soup, far, Vec2(v - far), kInf, 0.0);
    }
  }
  // A square with vertices on the axes: axis-aligned rays through vertices.
  const auto square = gridfree::testing::MakeSquare(4);
  Bvh<2> sq;
  sq.Build(square.Vertices, square.Simplices);
  for (int i = -3; i <= 3; ++i)
  {
    const double y = i / 4.0;
    EXPECT_NEAR(sq.Intersect(Vec2(0, y), Vec2(1, 0)).t, 1.0, 0.0) << y;
    EXPECT_NEAR(sq.Intersect(Vec2(0, y), Vec2(-2, 0)).t, 0.5, 0.0) << y;
    EXPECT_NEAR(sq.Intersect(Vec2(y, 0), Vec2(0, -0.5)).t, 2.0, 0.0) << y;
  }
}

//------------------------------------------------------------------------------
TEST(BvhRays, VisibilityThroughThinWall)
{
  // A wall x in [0, 1e-9] (a closed thin box of 12 triangles) between
  // scattered clutter elsewhere; the wall spans y, z in [-1, 1].
  std::vector<Vec3> v;
  std::vector<Bvh<3>::Primitive> t;
  const double w = 1e-9;
  for (int i = 0; i < 8; ++i)
  {
    v.emplace_back((i & 1) ? w : 0.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
  }
  const int faces[6][4] = { { 0, 2, 6, 4 }, { 1, 5, 7, 3 }, { 0, 4, 5, 1 }, { 2, 3, 7, 6 },
    { 0, 1, 3, 2 }, { 4, 6, 7, 5 } };
  for (const auto& f : faces)
  {
    t.push_back({ f[0], f[1], f[2] });
    t.push_back({ f[0], f[2], f[3] });
  }
  Bvh<3> bvh;
  bvh.Build(v, t);
  std::mt19937_64 rng(800);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  std::uniform_real_distribution<double> side(1e-6, 5.0);
  const double eps = 1e-9;
  for (int i = 0; i < 20000; ++i)
  {
    // Points whose segment crosses the wall inside [-1, 1]^2: pick the
    // crossing point, then the two ends on a line through it.
    const Vec3 cross(0.5 * w, u(rng), u(rng));
    const Vec3 dir(1.0, 0.3 * u(rng), 0.3 * u(rng));
    const Vec3 a = cross - side(rng) * dir;
    const Vec3 b = cross + side(rng) * dir;
    EXPECT_TRUE(bvh.Occluded(a, b - a, 1 - eps, eps)) << i;
    EXPECT_TRUE(bvh.Occluded(b, a - b, 1 - eps, eps)) << i;
    // Same side of the wall.
    const Vec3 c = cross - side(rng) * dir;
    const Vec3 e = a + Vec3(0, 0.1 * u(rng), 0.1 * u(rng));
    const Vec3& p = (c.x() < e.x()) ? c : e;
    EXPECT_FALSE(bvh.Occluded(a, c - a, 1 - eps, eps)) << i;
    EXPECT_FALSE(bvh.Occluded(p, b - b + (a - p), 1 - eps, eps)) << i;
  }
  // 2D: a wall segment.
  Bvh<2> wall;
  wall.Build({ Vec2(0, -1), Vec2(0, 1) }, { { 0, 1 } });
  for (int i = 0; i < 2000; ++i)
  {
    const Vec2 a(-side(rng), u(rng));
    const Vec2 b(side(rng), u(rng));
    EXPECT_TRUE(wall.Occluded(a, b - a, 1 - eps, eps));
    const Vec2 c(-side(rng), u(rng));
    EXPECT_FALSE(wall.Occluded(a, c - a, 1 - eps, eps));
  }
}

TEST(BvhRays, WindowsSelectHits)
{
  // Rays from outside through the sphere: the window picks the entry or the
  // exit, and Occluded agrees.
  const auto mesh = gridfree::testing::MakeIcosphere(3);
  Bvh<3> bvh;
  bvh.Build(mesh.Vertices, mesh.Simplices);
  std::mt19937_64 rng(900);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int i = 0; i < 2000; ++i)
  {
    const Vec3 o(-3.0, u(rng), u(rng));
    const Vec3 d(1.0, 0.1 * u(rng), 0.1 * u(rng));
    const RayHit<3> first = bvh.Intersect(o, d);
    ASSERT_TRUE(first.Hit());
    const RayHit<3> second = bvh.Intersect(o, d, kInf, first.t * (1 + 1e-9));
    ASSERT_TRUE(second.Hit());
    EXPECT_GT(second.t, first.t * (1 + 1e-6));
    EXPECT_EQ(bvh.Intersect(o, d, second.t, first.t * (1 + 1e-9)).t, second.t);
    EXPECT_FALSE(bvh.Intersect(o, d, second.t * (1 - 1e-9), first.t * (1 + 1e-9)).Hit());
    EXPECT_FALSE(bvh.Occluded(o, d, second.t * (1 - 1e-9), first.t * (1 + 1e-9)));
    EXPECT_FALSE(bvh.Intersect(o, d, first.t * (1 - 1e-9)).Hit());
    EXPECT_EQ(bvh.Intersect(o, d, first.t, first.t).t, first.t);
    EXPECT_FALSE(bvh.Intersect(o, d, kInf, second.t * (1 + 1e-9)).Hit());
    EXPECT_TRUE(bvh.Occluded(o, d, second.t, second.t));
  }
}
} // namespace
