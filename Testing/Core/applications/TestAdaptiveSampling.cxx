#include <gridfree/applications/AdaptiveSampling.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using gridfree::Point3;
using gridfree::SpreadSubset;
using gridfree::TaylorDisagreement;
using gridfree::TaylorNeighbour;

namespace
{
std::vector<Point3> Grid(int n, double z)
{
  std::vector<Point3> points;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      points.push_back({ i / double(n - 1), j / double(n - 1), z });
    }
  }
  return points;
}

double Distance(const Point3& a, const Point3& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}
} // namespace

TEST(AdaptiveSampling, SpreadSubsetCoversAnImageEvenly)
{
  const std::vector<Point3> points = Grid(200, 0.3);
  const std::vector<std::size_t> chosen = SpreadSubset(points, 400);
  EXPECT_GT(chosen.size(), 360u);
  EXPECT_LT(chosen.size(), 440u);
  // Every pixel lies within about one cell of a chosen pixel, and chosen
  // pixels are not bunched: the cell is about 1/20 of the side.
  double farthest = 0.0;
  for (const Point3& p : points)
  {
    double nearest = 1e300;
    for (std::size_t c : chosen)
    {
      nearest = std::min(nearest, Distance(p, points[c]));
    }
    farthest = std::max(farthest, nearest);
  }
  EXPECT_LT(farthest, 0.1);
  double closestPair = 1e300;
  for (std::size_t a = 0; a < chosen.size(); ++a)
  {
    for (std::size_t b = a + 1; b < chosen.size(); ++b)
    {
      closestPair = std::min(closestPair, Distance(points[chosen[a]], points[chosen[b]]));
    }
  }
  EXPECT_GT(closestPair, 0.02);
}

TEST(AdaptiveSampling, SpreadSubsetEdgeCases)
{
  EXPECT_TRUE(SpreadSubset({}, 10).empty());
  const std::vector<Point3> few = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
  EXPECT_EQ(SpreadSubset(few, 10).size(), 3u);
  const std::vector<Point3> same(50, Point3{ 2, 2, 2 });
  EXPECT_EQ(SpreadSubset(same, 10).size(), 1u);
  std::vector<Point3> withNaN = Grid(10, 0.0);
  withNaN[5][0] = std::nan("");
  for (std::size_t i : SpreadSubset(withNaN, 200))
  {
    EXPECT_NE(i, 5u);
  }
}

TEST(AdaptiveSampling, LinearFunctionsNeedNoRefinement)
{
  auto u = [](const Point3& p) { return 1.0 + 2.0 * p[0] - 3.0 * p[1] + 0.5 * p[2]; };
  std::vector<TaylorNeighbour> neighbours;
  for (const Point3& p : std::vector<Point3>{ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 1 }, { 1, 1, 0 } })
  {
    neighbours.push_back({ p, u(p), { 2.0, -3.0, 0.5 }, 0.0, { 0.0, 0.0, 0.0 } });
  }
  EXPECT_NEAR(TaylorDisagreement({ 0.4, 0.6, 0.2 }, neighbours.data(), 4), 0.0, 1e-12);
}

TEST(AdaptiveSampling, CurvatureIsDetectedAndGrowsWithSpacing)
{
  // u = x² - y²: predictions from distance d disagree by O(d²).
  auto neighboursAt = [](double d) {
    std::vector<TaylorNeighbour> n;
    for (const Point3& p : std::vector<Point3>{ { d, 0, 0 }, { -d, 0, 0 }, { 0, d, 0 }, { 0, -d, 0 } })
    {
      n.push_back({ p, p[0] * p[0] - p[1] * p[1], { 2 * p[0], -2 * p[1], 0.0 }, 0.0, { 0, 0, 0 } });
    }
    return n;
  };
  const double coarse = TaylorDisagreement({ 0, 0, 0 }, neighboursAt(0.2).data(), 4);
  const double fine = TaylorDisagreement({ 0, 0, 0 }, neighboursAt(0.1).data(), 4);
  EXPECT_GT(coarse, 0.0);
  // Predictions ±d² ⇒ the spread's variance scales as d⁴.
  EXPECT_NEAR(coarse / fine, 16.0, 1e-9);
}

TEST(AdaptiveSampling, NoiseAloneGivesNoDisagreementOnAverage)
{
  // Linear u, each neighbour's value and gradient noisy with the variances
  // it reports: the noise correction makes the mean disagreement zero.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Point3 x = { 0.1, 0.2, 0.0 };
  const std::vector<Point3> positions = { { 0, 0, 0 }, { 0.3, 0, 0 }, { 0, 0.3, 0 }, { 0.3, 0.3, 0 },
    { 0.15, -0.1, 0.1 }, { -0.1, 0.2, 0.0 } };
  const int trials = 20000;
  double sum = 0.0, sumSquares = 0.0;
  for (int t = 0; t < trials; ++t)
  {
    std::vector<TaylorNeighbour> n;
    for (std::size_t i = 0; i < positions.size(); ++i)
    {
      const Point3& p = positions[i];
      const double valueVariance = 0.01 * (1 + i % 2);
      const Point3 gradientVariance = { 0.05, 0.08, 0.02 };
      TaylorNeighbour s{ p, 2.0 * p[0] + p[1], { 2.0, 1.0, 0.0 }, valueVariance, gradientVariance };
      s.Value += std::sqrt(valueVariance) * normal(rng);
      for (int a = 0; a < 3; ++a)
      {
        s.Gradient[a] += std::sqrt(gradientVariance[a]) * normal(rng);
      }
      n.push_back(s);
    }
    const double d = TaylorDisagreement(x, n.data(), static_cast<int>(n.size()));
    sum += d;
    sumSquares += d * d;
  }
  const double mean = sum / trials;
  const double standardError = std::sqrt((sumSquares / trials - mean * mean) / trials);
  EXPECT_LT(std::abs(mean), 5.0 * standardError);
  // Without the correction (the mean predicted noise variance, about 0.02
  // here) the mean would be far from zero: the test can tell.
  double noise = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    noise += 0.01 * (1 + i % 2);
    const double offset[3] = { x[0] - positions[i][0], x[1] - positions[i][1],
      x[2] - positions[i][2] };
    noise += offset[0] * offset[0] * 0.05 + offset[1] * offset[1] * 0.08 +
      offset[2] * offset[2] * 0.02;
  }
  noise /= positions.size();
  EXPECT_GT(noise, 20.0 * standardError);
}

TEST(AdaptiveSampling, FewerThanTwoNeighboursAlwaysRefine)
{
  TaylorNeighbour one{ { 0, 0, 0 }, 1.0, { 0, 0, 0 }, 0.0, { 0, 0, 0 } };
  EXPECT_TRUE(std::isinf(TaylorDisagreement({ 1, 0, 0 }, &one, 1)));
  EXPECT_TRUE(std::isinf(TaylorDisagreement({ 1, 0, 0 }, nullptr, 0)));
}
