// The searches of the hierarchy run with the instruction set chosen at run
// time (SimdDispatch.h). Every level this CPU supports must give the same
// bits as the SSE2 baseline, which itself must equal brute force: distances,
// closest points and their primitives and weights, relaxed lower bounds,
// hinted queries and ray hits, on random soups, a closed sphere seen from
// its centre (all triangles equidistant) and coplanar overlapping triangles.
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/SimdDispatch.h>
#include "RandomSoups.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

namespace
{
using gridfree::Bvh;
using gridfree::SimdLevel;
using gridfree::Vec;
using gridfree::testing::BruteForceSquaredDistance;
using gridfree::testing::Soup;

std::vector<SimdLevel> SupportedLevels()
{
  std::vector<SimdLevel> levels;
  for (const SimdLevel l : { SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512 })
  {
    if (l <= gridfree::CpuSimdLevel())
    {
      levels.push_back(l);
    }
  }
  return levels;
}

/// Everything a query can answer, to compare bit for bit.
template <int DIM>
struct Answers
{
  std::vector<double> Values;
  std::vector<std::int64_t> Ids;

  void Add(double v) { this->Values.push_back(v); }
  void Add(const Vec<DIM>& v)
  {
    for (int k = 0; k < DIM; ++k)
    {
      this->Values.push_back(v[k]);
    }
  }
};

template <int DIM>
bool SameBits(const Answers<DIM>& a, const Answers<DIM>& b)
{
  return a.Ids == b.Ids && a.Values.size() == b.Values.size() &&
    std::memcmp(a.Values.data(), b.Values.data(), a.Values.size() * sizeof(double)) == 0;
}

template <int DIM>
Answers<DIM> Ask(const Bvh<DIM>& bvh, const std::vector<Vec<DIM>>& queries,
  const std::vector<Vec<DIM>>& directions)
{
  Answers<DIM> a;
  typename Bvh<DIM>::NearestHint hint; // carried from query to query, as a walk does
  for (std::size_t i = 0; i < queries.size(); ++i)
  {
    const Vec<DIM>& x = queries[i];
    a.Add(bvh.SquaredDistance(x));
    const auto r = bvh.ClosestPoint(x);
    a.Add(r.distance);
    a.Add(r.point);
    a.Add(r.barycentric);
    a.Ids.push_back(r.primitive);
    bool exact = false;
    a.Add(bvh.DistanceLowerBound(x, 0.2, 1e-3, exact, &hint));
    a.Ids.push_back(exact);
    a.Add(bvh.SquaredDistance(x, hint));
    a.Ids.push_back(hint.Primitive);
    const auto hit = bvh.Intersect(x, directions[i]);
    a.Add(hit.t);
    a.Ids.push_back(hit.primitive);
    a.Ids.push_back(bvh.Occluded(x, directions[i], 0.5));
  }
  return a;
}

/// Queries spread over the box, near and on primitives, and far away.
template <int DIM>
void MakeQueries(const Soup<DIM>& soup, int count, std::uint64_t seed,
  std::vector<Vec<DIM>>& queries, std::vector<Vec<DIM>>& directions)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::normal_distribution<double> gauss;
  auto direction = [&]()
  {
    Vec<DIM> d;
    for (int k = 0; k < DIM; ++k)
    {
      d[k] = gauss(rng);
    }
    return d;
  };
  for (int i = 0; i < count; ++i)
  {
    Vec<DIM> x;
    switch (i % 3)
    {
      case 0:
        for (int k = 0; k < DIM; ++k)
        {
          x[k] = u(rng);
        }
        break;
      case 1:
        x = soup.Vertices[soup.Primitives[rng() % soup.Primitives.size()][0]] +
          std::pow(10.0, -8.0 + 7.0 * (u(rng) + 0.2) / 1.4) * direction();
        break;
      default:
        x = 50.0 * direction();
    }
    queries.push_back(x);
    directions.push_back(direction());
  }
}

template <int DIM>
void CheckAllLevels(const Soup<DIM>& soup, const std::vector<Vec<DIM>>& queries,
  const std::vector<Vec<DIM>>& directions)
{
  Bvh<DIM> bvh;
  bvh.Build(soup.Vertices, soup.Primitives);
  ASSERT_EQ(bvh.SetSimdLevel(SimdLevel::Sse2), SimdLevel::Sse2);
  const Answers<DIM> baseline = Ask(bvh, queries, directions);

  // The baseline is exact: its distances are the brute-force minimum.
  for (std::size_t i = 0; i < queries.size(); ++i)
  {
    const double ref2 = BruteForceSquaredDistance(soup, queries[i]);
    const double d2 = baseline.Values[i * (1 + 1 + 2 * DIM + 1 + 1 + 1)];
    ASSERT_NEAR(std::sqrt(d2), std::sqrt(ref2), 1e-12 * std::sqrt(ref2) + 1e-13)
      << "query " << queries[i].transpose();
  }

  for (const SimdLevel level : SupportedLevels())
  {
    ASSERT_EQ(bvh.SetSimdLevel(level), level);
    EXPECT_EQ(bvh.GetSimdLevel(), level);
    EXPECT_TRUE(SameBits(Ask(bvh, queries, directions), baseline))
      << gridfree::SimdLevelName(level) << " differs from sse2";
  }
}
} // namespace

TEST(SimdDispatch, LevelsAndNames)
{
  SimdLevel l = SimdLevel::Sse2;
  EXPECT_TRUE(gridfree::ParseSimdLevel("avx512", l));
  EXPECT_EQ(l, SimdLevel::Avx512);
  EXPECT_TRUE(gridfree::ParseSimdLevel("avx2", l));
  EXPECT_EQ(l, SimdLevel::Avx2);
  EXPECT_TRUE(gridfree::ParseSimdLevel("sse2", l));
  EXPECT_EQ(l, SimdLevel::Sse2);
  EXPECT_FALSE(gridfree::ParseSimdLevel("avx", l));
  EXPECT_FALSE(gridfree::ParseSimdLevel(nullptr, l));
  EXPECT_EQ(l, SimdLevel::Sse2);

  // A new hierarchy uses the default level; asking for more than the CPU
  // has gives what it has.
  Bvh<3> bvh;
  EXPECT_EQ(bvh.GetSimdLevel(), gridfree::DefaultSimdLevel());
  EXPECT_LE(gridfree::DefaultSimdLevel(), gridfree::CpuSimdLevel());
  EXPECT_EQ(bvh.SetSimdLevel(SimdLevel::Avx512), gridfree::CpuSimdLevel());

  // GRIDFREE_SIMD lowers the default (the test is also run with it set).
  SimdLevel requested;
  if (gridfree::ParseSimdLevel(std::getenv("GRIDFREE_SIMD"), requested))
  {
    EXPECT_LE(gridfree::DefaultSimdLevel(), requested);
  }
  else
  {
    EXPECT_EQ(gridfree::DefaultSimdLevel(), gridfree::CpuSimdLevel());
  }
  std::cout << "CPU supports " << gridfree::SimdLevelName(gridfree::CpuSimdLevel())
            << "; hierarchies use " << gridfree::SimdLevelName(gridfree::DefaultSimdLevel())
            << " by default\n";
}

TEST(SimdDispatch, SoupsGiveTheSameBitsAtEveryLevel)
{
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
  {
    const Soup<3> soup3 = gridfree::testing::MakeSoup<3>(3000, seed);
    std::vector<gridfree::Vec3> q3, d3;
    MakeQueries(soup3, 600, seed + 10, q3, d3);
    CheckAllLevels(soup3, q3, d3);

    const Soup<2> soup2 = gridfree::testing::MakeSoup<2>(3000, seed);
    std::vector<gridfree::Vec2> q2, d2;
    MakeQueries(soup2, 600, seed + 20, q2, d2);
    CheckAllLevels(soup2, q2, d2);
  }
}

TEST(SimdDispatch, AdversarialCasesGiveTheSameBitsAtEveryLevel)
{
  // A closed sphere: from near its centre every triangle is nearly
  // equidistant, the worst case for pruning.
  const auto sphere = gridfree::testing::MakeIcosphere(4);
  Soup<3> closed;
  closed.Vertices = sphere.Vertices;
  for (const auto& s : sphere.Simplices)
  {
    closed.Primitives.push_back({ s[0], s[1], s[2] });
  }
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  std::vector<gridfree::Vec3> queries, directions;
  for (int i = 0; i < 200; ++i)
  {
    const gridfree::Vec3 d(gauss(rng), gauss(rng), gauss(rng));
    queries.push_back((i == 0 ? 0.0 : 1e-3 * (i % 7)) * d);
    directions.push_back(gridfree::Vec3(gauss(rng), gauss(rng), gauss(rng)));
  }
  CheckAllLevels(closed, queries, directions);

  // Coplanar overlapping triangles: many exact ties in the plane z = 0.
  Soup<3> coplanar;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 400; ++i)
  {
    const auto base = static_cast<std::int64_t>(coplanar.Vertices.size());
    const gridfree::Vec3 c(0.5 * u(rng), 0.5 * u(rng), 0.0);
    coplanar.Vertices.push_back(c);
    coplanar.Vertices.push_back(c + gridfree::Vec3(0.5, 0.0, 0.0));
    coplanar.Vertices.push_back(c + gridfree::Vec3(0.0, 0.5, 0.0));
    coplanar.Primitives.push_back({ base, base + 1, base + 2 });
  }
  queries.clear();
  directions.clear();
  for (int i = 0; i < 300; ++i)
  {
    queries.emplace_back(u(rng), u(rng), (i % 3 - 1) * 0.1 * u(rng));
    directions.emplace_back(gauss(rng), gauss(rng), gauss(rng));
  }
  CheckAllLevels(coplanar, queries, directions);
}
