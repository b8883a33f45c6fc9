// Silhouettes of the Neumann part for walk on stars (SilhouetteTree.h): the
// candidates are the reflex vertices and edges, the test agrees with a
// sight-line construction that shares no code with it, and the tree's
// closest silhouette equals a loop over every candidate on closed block
// shapes, bumpy spheres seen from inside and outside, and random soups.
#include <gridfree/stars/SilhouetteTree.h>

#include "BlockShapes.h"
#include "RandomSoups.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using namespace gridfree;
using namespace gridfree::testing;

template <int DIM>
std::vector<std::array<std::int64_t, DIM>> Primitives(const SimplexMesh<DIM>& mesh)
{
  return std::vector<std::array<std::int64_t, DIM>>(mesh.Simplices.begin(), mesh.Simplices.end());
}

// The closest silhouette by a loop over every candidate.
template <int DIM>
double BruteForce(const SilhouetteTree<DIM>& tree, const Vec<DIM>& x, double rMax)
{
  double best = rMax;
  double best2 = rMax * rMax;
  for (const SilhouetteCandidate<DIM>& c : tree.CandidateList())
  {
    const Vec<DIM> p = c.ClosestPoint(x);
    const double d2 = (x - p).squaredNorm();
    if (d2 < best2 && IsSilhouette(c, x, p, std::sqrt(d2), tree.OnCandidateTolerance()))
    {
      best2 = d2;
      best = std::sqrt(d2);
    }
  }
  return best;
}

// Queries: uniform in the box grown by half, near vertices, and exactly on
// vertices; each with rMax either infinite or random.
template <int DIM>
void ExpectTreeEqualsBruteForce(
  const std::vector<Vec<DIM>>& vertices, const std::vector<std::array<std::int64_t, DIM>>& prims,
  int queries, std::uint32_t seed)
{
  SilhouetteTree<DIM> tree;
  tree.Build(vertices, prims);
  BoundingBox<DIM> box;
  for (const Vec<DIM>& v : vertices)
  {
    box.Expand(v);
  }
  const Vec<DIM> extent = box.Extent();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int finite = 0;
  for (int q = 0; q < queries; ++q)
  {
    Vec<DIM> x;
    const int kind = q % 3;
    const Vec<DIM>& v = vertices[rng() % vertices.size()];
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = kind == 0 ? box.Min[k] - 0.25 * extent[k] + 1.5 * extent[k] * u(rng)
        : kind == 1    ? v[k] + 0.02 * extent.norm() * (u(rng) - 0.5)
                       : v[k];
    }
    const double rMax =
      q % 2 ? std::numeric_limits<double>::infinity() : 2.0 * extent.norm() * u(rng);
    const double expected = BruteForce(tree, x, rMax);
    const double got = tree.ClosestDistance(x, rMax);
    ASSERT_EQ(got, expected) << "query " << q << " at " << x.transpose();
    finite += std::isfinite(got) && got < rMax ? 1 : 0;
  }
  // The comparison means something only if silhouettes were found.
  if (tree.NumberOfCandidates() > 0)
  {
    EXPECT_GT(finite, queries / 10);
  }
}

// An icosphere with radial bumps (reflex edges in its dents), optionally
// turned inside out (the domain is then outside it: every edge reflex).
SimplexMesh<3> BumpySphere(bool insideOut)
{
  SimplexMesh<3> mesh = MakeIcosphere(3);
  for (Vec3& v : mesh.Vertices)
  {
    v *= 1.0 + 0.25 * std::sin(5.0 * v[0]) * std::sin(4.0 * v[1] + 1.0) * std::cos(3.0 * v[2]);
  }
  if (insideOut)
  {
    for (auto& t : mesh.Simplices)
    {
      std::swap(t[1], t[2]);
    }
  }
  return mesh;
}

SimplexMesh<2> BumpyCircle(bool insideOut)
{
  SimplexMesh<2> mesh = MakeCircle(400);
  for (Vec2& v : mesh.Vertices)
  {
    const double a = std::atan2(v[1], v[0]);
    v *= 1.0 + 0.3 * std::sin(7.0 * a);
  }
  if (insideOut)
  {
    for (auto& s : mesh.Simplices)
    {
      std::swap(s[0], s[1]);
    }
  }
  return mesh;
}

TEST(SilhouetteTree, CandidatesAreTheReflexVerticesAndEdges)
{
  // L of three unit squares: one reflex vertex, at (1, 1).
  const SimplexMesh<2> l2 = MakeBlockShape<2>({ { 0, 0 }, { 1, 0 }, { 0, 1 } }, 4);
  const auto c2 = SilhouetteTree<2>::MakeCandidates(l2.Vertices, Primitives(l2));
  ASSERT_EQ(c2.size(), 1u);
  EXPECT_EQ(c2[0].A, Vec2(1.0, 1.0));
  EXPECT_FALSE(c2[0].Always);
  // The same L as a prism two cubes high: the reflex edge along z, cut into
  // 2 × 3 pieces.
  const SimplexMesh<3> l3 =
    MakeBlockShape<3>({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 } }, 3);
  const auto c3 = SilhouetteTree<3>::MakeCandidates(l3.Vertices, Primitives(l3));
  ASSERT_EQ(c3.size(), 6u);
  for (const auto& c : c3)
  {
    EXPECT_DOUBLE_EQ(c.A[0], 1.0);
    EXPECT_DOUBLE_EQ(c.A[1], 1.0);
    EXPECT_DOUBLE_EQ(c.B[0], 1.0);
    EXPECT_DOUBLE_EQ(c.B[1], 1.0);
  }
  // Turned inside out (the domain outside the L), its convex corners are the
  // reflex ones: 5 in 2D; and an open polyline's two ends always count.
  SimplexMesh<2> out2 = l2;
  for (auto& s : out2.Simplices)
  {
    std::swap(s[0], s[1]);
  }
  EXPECT_EQ(SilhouetteTree<2>::MakeCandidates(out2.Vertices, Primitives(out2)).size(), 5u);
  SimplexMesh<2> open = l2;
  open.Simplices.pop_back();
  const auto cOpen = SilhouetteTree<2>::MakeCandidates(open.Vertices, Primitives(open));
  int always = 0;
  for (const auto& c : cOpen)
  {
    always += c.Always ? 1 : 0;
  }
  EXPECT_EQ(always, 2);
}

// Silhouette iff the candidate's two neighbours (2D: the vertices before and
// after it; 3D: the triangles' third vertices) lie on the same side of the
// line (plane) through x and the candidate.
TEST(SilhouetteTree, TestAgreesWithSightLines2D)
{
  const SimplexMesh<2> mesh = BumpyCircle(false);
  const std::size_t n = mesh.Vertices.size();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.4, 1.4);
  int silhouettes = 0, checked = 0;
  for (int q = 0; q < 400; ++q)
  {
    const Vec2 x(u(rng), u(rng));
    for (std::size_t i = 0; i < n; ++i)
    {
      const Vec2& a = mesh.Vertices[(i + n - 1) % n];
      const Vec2& b = mesh.Vertices[i];
      const Vec2& c = mesh.Vertices[(i + 1) % n];
      SilhouetteCandidate<2> cand;
      cand.A = cand.B = b;
      cand.N0 = OutwardUnitNormal<2>(mesh.Vertices, std::array<std::int64_t, 2>{ std::int64_t((i + n - 1) % n), std::int64_t(i) });
      cand.N1 = OutwardUnitNormal<2>(mesh.Vertices, std::array<std::int64_t, 2>{ std::int64_t(i), std::int64_t((i + 1) % n) });
      const Vec2 s = b - x;
      const double sa = s[0] * (a - b)[1] - s[1] * (a - b)[0];
      const double sc = s[0] * (c - b)[1] - s[1] * (c - b)[0];
      if (std::abs(sa) < 1e-3 * (a - b).norm() * s.norm() || std::abs(sc) < 1e-3 * (c - b).norm() * s.norm())
      {
        continue; // near-degenerate sight lines: the tolerances decide
      }
      const bool sameSide = (sa > 0) == (sc > 0);
      EXPECT_EQ(IsSilhouette(cand, x, b, s.norm(), 0.0), sameSide);
      silhouettes += sameSide ? 1 : 0;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100000);
  EXPECT_GT(silhouettes, 1000);
}

TEST(SilhouetteTree, TestAgreesWithSightPlanes3D)
{
  const SimplexMesh<3> mesh = BumpySphere(false);
  // Every edge once, with its two triangles' third vertices.
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::array<std::int64_t, 3>>> edges;
  for (const auto& t : mesh.Simplices)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = t[k], b = t[(k + 1) % 3];
      edges[{ std::min(a, b), std::max(a, b) }].push_back(t);
    }
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  int silhouettes = 0, checked = 0;
  for (int q = 0; q < 40; ++q)
  {
    const Vec3 x(u(rng), u(rng), u(rng));
    for (const auto& [key, tris] : edges)
    {
      ASSERT_EQ(tris.size(), 2u);
      const Vec3& p = mesh.Vertices[key.first];
      const Vec3& r = mesh.Vertices[key.second];
      auto third = [&](const std::array<std::int64_t, 3>& t) {
        for (std::int64_t v : t)
        {
          if (v != key.first && v != key.second)
          {
            return mesh.Vertices[v];
          }
        }
        return Vec3(Vec3::Zero());
      };
      SilhouetteCandidate<3> cand;
      cand.A = p;
      cand.B = r;
      cand.N0 = OutwardUnitNormal<3>(mesh.Vertices, tris[0]);
      cand.N1 = OutwardUnitNormal<3>(mesh.Vertices, tris[1]);
      const Vec3 m = (p - x).cross(r - x);
      const double s0 = m.dot(third(tris[0]) - p);
      const double s1 = m.dot(third(tris[1]) - p);
      const double scale = m.norm() * (r - p).norm();
      if (std::abs(s0) < 1e-3 * scale || std::abs(s1) < 1e-3 * scale)
      {
        continue;
      }
      const Vec3 c = cand.ClosestPoint(x);
      EXPECT_EQ(IsSilhouette(cand, x, c, (x - c).norm(), 0.0), (s0 > 0) == (s1 > 0));
      silhouettes += (s0 > 0) == (s1 > 0) ? 1 : 0;
      ++checked;
    }
  }
  EXPECT_GT(checked, 50000);
  EXPECT_GT(silhouettes, 1000);
}

TEST(SilhouetteTree, TreeEqualsBruteForceOnClosedShapes)
{
  const SimplexMesh<2> comb2 =
    MakeBlockShape<2>({ { 0, 0 }, { 1, 0 }, { 2, 0 }, { 3, 0 }, { 4, 0 }, { 0, 1 }, { 2, 1 }, { 4, 1 }, { 0, 2 }, { 2, 2 }, { 4, 2 } }, 5, 0.4);
  ExpectTreeEqualsBruteForce<2>(comb2.Vertices, Primitives(comb2), 3000, 1);
  for (bool insideOut : { false, true })
  {
    const SimplexMesh<2> circle = BumpyCircle(insideOut);
    ExpectTreeEqualsBruteForce<2>(circle.Vertices, Primitives(circle), 3000, 2);
    const SimplexMesh<3> sphere = BumpySphere(insideOut);
    ExpectTreeEqualsBruteForce<3>(sphere.Vertices, Primitives(sphere), 1500, 3);
  }
  const SimplexMesh<3> u3 = MakeBlockShape<3>(
    { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 }, { 2, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 2, 0, 1 }, { 0, 1, 1 }, { 2, 1, 1 } }, 3);
  ExpectTreeEqualsBruteForce<3>(u3.Vertices, Primitives(u3), 1500, 4);
}

TEST(SilhouetteTree, TreeEqualsBruteForceOnRandomSoups)
{
  for (std::uint64_t seed : { 1u, 2u, 3u })
  {
    const Soup<2> soup2 = MakeSoup<2>(2000, seed);
    ExpectTreeEqualsBruteForce<2>(soup2.Vertices, soup2.Primitives, 1000, 10 + seed);
    const Soup<3> soup3 = MakeSoup<3>(2000, seed);
    ExpectTreeEqualsBruteForce<3>(soup3.Vertices, soup3.Primitives, 1000, 20 + seed);
  }
}
} // namespace
