// Random streams: determinism, independence of nearby keys, uniformity.
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

using namespace gridfree;

TEST(Random, SameKeySameStream)
{
  const double p[3] = { 0.1, 0.2, 0.3 };
  RandomStream a(PointKey(5, p), 3), b(PointKey(5, p), 3);
  for (int i = 0; i < 100; ++i)
  {
    ASSERT_EQ(a.NextUInt32(), b.NextUInt32());
  }
}

TEST(Random, NearbyPointsSeedsAndWalksDiffer)
{
  const double p[3] = { 0.1, 0.2, 0.3 };
  double q[3] = { 0.1, 0.2, 0.3 };
  q[2] = std::nextafter(q[2], 1.0); // one ulp away
  std::set<std::uint32_t> first;
  first.insert(RandomStream(PointKey(5, p), 0).NextUInt32());
  first.insert(RandomStream(PointKey(5, q), 0).NextUInt32());
  first.insert(RandomStream(PointKey(6, p), 0).NextUInt32());
  first.insert(RandomStream(PointKey(5, p), 1).NextUInt32());
  EXPECT_EQ(first.size(), 4u);
}

TEST(Random, SignedZeroIsTheSamePoint)
{
  const double p[3] = { 0.0, 1.0, 2.0 };
  const double q[3] = { -0.0, 1.0, 2.0 };
  EXPECT_EQ(PointKey(1, p), PointKey(1, q));
}

// Kolmogorov-Smirnov statistic of NextDouble over many short streams (the way
// walks use them): first draws of consecutive walk numbers must be uniform.
TEST(Random, FirstDrawsOfConsecutiveWalksAreUniform)
{
  const double p[3] = { 0.5, 0.5, 0.5 };
  const std::uint64_t key = PointKey(0, p);
  const int n = 20000;
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i)
  {
    RandomStream rng(key, static_cast<std::uint64_t>(i));
    u[i] = rng.NextDouble();
    ASSERT_GE(u[i], 0.0);
    ASSERT_LT(u[i], 1.0);
  }
  std::sort(u.begin(), u.end());
  double d = 0.0;
  for (int i = 0; i < n; ++i)
  {
    d = std::max({ d, std::abs(u[i] - double(i) / n), std::abs(u[i] - double(i + 1) / n) });
  }
  // 99.9% critical value of the KS statistic: 1.95 / sqrt(n).
  EXPECT_LT(d, 1.95 / std::sqrt(double(n)));
}

template <int DIM>
void CheckSphereMoments()
{
  const double p[3] = { 1, 2, 3 };
  RandomStream rng(PointKey(0, p), 0);
  const int n = 200000;
  Vec<DIM> mean = Vec<DIM>::Zero();
  Eigen::Matrix<double, DIM, DIM> second = Eigen::Matrix<double, DIM, DIM>::Zero();
  for (int i = 0; i < n; ++i)
  {
    const Vec<DIM> v = SampleUnitSphere<DIM>(rng);
    ASSERT_NEAR(v.norm(), 1.0, 1e-12);
    mean += v;
    second += v * v.transpose();
  }
  mean /= n;
  second /= n;
  // E[v] = 0 and E[v v^T] = I / DIM; standard errors ~ 1/sqrt(n) ~ 2e-3.
  for (int i = 0; i < DIM; ++i)
  {
    EXPECT_NEAR(mean[i], 0.0, 0.01);
    for (int j = 0; j < DIM; ++j)
    {
      EXPECT_NEAR(second(i, j), i == j ? 1.0 / DIM : 0.0, 0.01);
    }
  }
}

TEST(SphereSampling, CircleIsUniform)
{
  CheckSphereMoments<2>();
}

TEST(SphereSampling, SphereIsUniform)
{
  CheckSphereMoments<3>();
}
