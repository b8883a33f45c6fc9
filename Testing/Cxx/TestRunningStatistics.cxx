#include "RunningStatistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using gridfree::RunningStatistics;

TEST(RunningStatistics, MatchesTwoPassFormulas)
{
  std::mt19937 rng(1);
  std::normal_distribution<double> normal(1e6, 2.0); // large mean, small spread
  RunningStatistics stats(2);
  std::vector<double> a, b;
  for (int i = 0; i < 1000; ++i)
  {
    const double s[2] = { normal(rng), -3.0 * i };
    a.push_back(s[0]);
    b.push_back(s[1]);
    stats.Add(s);
  }
  auto twoPass = [](const std::vector<double>& x, double& mean, double& var) {
    mean = 0.0;
    for (double v : x)
    {
      mean += v;
    }
    mean /= x.size();
    var = 0.0;
    for (double v : x)
    {
      var += (v - mean) * (v - mean);
    }
    var /= (x.size() - 1);
  };
  double meanA, varA, meanB, varB;
  twoPass(a, meanA, varA);
  twoPass(b, meanB, varB);
  EXPECT_NEAR(stats.GetMean(0), meanA, 1e-9);
  EXPECT_NEAR(stats.SampleVariance(0), varA, 1e-6 * varA);
  EXPECT_NEAR(stats.GetMean(1), meanB, 1e-9);
  EXPECT_NEAR(stats.SampleVariance(1), varB, 1e-9 * varB);
  EXPECT_NEAR(stats.VarianceOfMean(0), varA / 1000.0, 1e-6 * varA / 1000.0);
  EXPECT_EQ(stats.SampleCount(), 1000u);
}

TEST(RunningStatistics, VarianceUndefinedBelowTwoSamples)
{
  RunningStatistics stats(1);
  const double s = 3.0;
  stats.Add(&s);
  EXPECT_TRUE(std::isnan(stats.VarianceOfMean(0)));
  stats.Reset();
  EXPECT_EQ(stats.SampleCount(), 0u);
}
