#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/statistics/RunningSumsCache.h>

#include <gtest/gtest.h>

#include <array>
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

// A saved and restored state continues bit for bit: the basis of
// progressive refinement (RunningSumsCache.h).
TEST(RunningStatistics, RestoredStateContinuesBitForBit)
{
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(3.0, 2.0);
  std::vector<std::array<double, 2>> samples(1000);
  for (auto& s : samples)
  {
    s = { normal(rng), 1e6 + normal(rng) };
  }
  gridfree::RunningStatistics all(2), first(2), resumed(2);
  for (const auto& s : samples)
  {
    all.Add(s.data());
  }
  for (std::size_t i = 0; i < 377; ++i)
  {
    first.Add(samples[i].data());
  }
  std::size_t count;
  double mean[2], m2[2];
  first.SaveState(count, mean, m2);
  resumed.RestoreState(count, mean, m2);
  for (std::size_t i = 377; i < samples.size(); ++i)
  {
    resumed.Add(samples[i].data());
  }
  for (int c = 0; c < 2; ++c)
  {
    EXPECT_EQ(resumed.GetMean(c), all.GetMean(c));
    EXPECT_EQ(resumed.VarianceOfMean(c), all.VarianceOfMean(c));
  }
  EXPECT_EQ(resumed.SampleCount(), all.SampleCount());
}

TEST(RunningSumsCache, ResumesOnlyWhatItKept)
{
  gridfree::RunningSumsCache cache;
  EXPECT_FALSE(cache.CanResume(10, 3, true, 0.0, 1000)); // nothing kept
  cache.Reset(10, 3, true);
  gridfree::RunningStatistics stats(3);
  const double sample[3] = { 1.0, 2.0, 4.0 };
  stats.Add(sample);
  stats.Add(sample);
  gridfree::WalkCounters counters;
  counters.Walks = 2;
  counters.Steps = 9;
  cache.Save(4, stats, counters, 1);
  gridfree::RunningStatistics history(3);
  const double blockSample[3] = { -1.0, 0.5, 8.0 };
  history.Add(blockSample);
  cache.SaveHistory(4, history);
  cache.SetKeptWalks(300);
  EXPECT_TRUE(cache.CanResume(10, 3, true, 0.0, 300));
  EXPECT_TRUE(cache.CanResume(10, 3, true, 0.0, 4096));
  EXPECT_FALSE(cache.CanResume(10, 3, true, 0.0, 299));  // fewer walks than kept
  EXPECT_FALSE(cache.CanResume(11, 3, true, 0.0, 4096));  // another probe
  EXPECT_FALSE(cache.CanResume(10, 2, true, 0.0, 4096));  // another layout
  EXPECT_FALSE(cache.CanResume(10, 3, false, 0.0, 4096)); // another estimator
  gridfree::RunningStatistics loaded(3);
  gridfree::WalkCounters loadedCounters;
  unsigned char status = 0;
  cache.Load(4, loaded, loadedCounters, status);
  EXPECT_EQ(loaded.SampleCount(), 2u);
  EXPECT_EQ(loaded.GetMean(2), 4.0);
  EXPECT_EQ(loadedCounters.Steps, 9u);
  EXPECT_EQ(status, 1);
  gridfree::RunningStatistics loadedHistory(3);
  cache.LoadHistory(4, loadedHistory);
  EXPECT_EQ(loadedHistory.SampleCount(), 1u);
  EXPECT_EQ(loadedHistory.GetMean(0), -1.0);
  EXPECT_EQ(loadedHistory.GetMean(2), 8.0);
  // A point never saved loads as empty.
  cache.LoadHistory(5, loadedHistory);
  EXPECT_EQ(loadedHistory.SampleCount(), 0u);
  EXPECT_FALSE(cache.Stopped(4)); // a fixed count has no target
  EXPECT_GT(cache.MemoryBytes(), 0u);

  // Target-error batches: the same target, a tighter one or a fixed count
  // resumes (not a looser target), and each point's stop is kept.
  cache.Reset(10, 3, false, 0.5);
  cache.Save(2, stats, counters, 0, true);
  cache.Save(3, stats, counters, 0, false);
  cache.SetKeptWalks(256, false);
  EXPECT_TRUE(cache.CanResume(10, 3, false, 0.5, 512));
  EXPECT_TRUE(cache.CanResume(10, 3, false, 0.25, 512)); // a tighter target
  EXPECT_TRUE(cache.CanResume(10, 3, false, 0.0, 512));  // a fixed count
  EXPECT_FALSE(cache.CanResume(10, 3, false, 1.0, 512)); // a looser target
  EXPECT_FALSE(cache.Uniform());
  EXPECT_TRUE(cache.Stopped(2));
  EXPECT_FALSE(cache.Stopped(3));
  cache.Retarget(0.25);
  EXPECT_DOUBLE_EQ(cache.KeptTarget(), 0.25);
  EXPECT_TRUE(cache.Stopped(2)); // checked again by the batch
  cache.Retarget(0.0);
  EXPECT_FALSE(cache.Stopped(2)); // a fixed count has no stops
  EXPECT_FALSE(cache.CanResume(10, 3, false, 0.5, 512)); // kept for a fixed count now

  // After an abort each point holds its own count: the most bounds a
  // resume, and the fewest is what every point resumed from.
  cache.Reset(4, 3, false);
  gridfree::RunningStatistics partial(3);
  for (int k = 0; k < 5; ++k)
  {
    partial.Add(sample);
  }
  cache.Save(1, partial, counters, 0);
  cache.KeepWhatEachPointHolds();
  EXPECT_TRUE(cache.Interrupted());
  EXPECT_FALSE(cache.Uniform());
  EXPECT_EQ(cache.KeptWalks(), 5u);
  EXPECT_EQ(cache.FewestWalks(), 0u);
  EXPECT_EQ(cache.Walks(1), 5u);
  EXPECT_TRUE(cache.CanResume(4, 3, false, 0.0, 5));
  EXPECT_FALSE(cache.CanResume(4, 3, false, 0.0, 4));
  cache.Clear();
  EXPECT_FALSE(cache.CanResume(10, 3, true, 0.0, 4096));
  EXPECT_EQ(cache.MemoryBytes(), 0u);
}
