// Tests of gridfree/problem/Problem.h: a problem built once answers batches
// of points, calibrated, with the same bits for any thread count and either
// schedule (points over threads, or one point's walks over threads),
// resumably, and stops when its progress callback says so.
#include <gridfree/problem/Problem.h>
#include "EstimatorChecks.h"
#include "MixedShapes.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
const Field<3> Saddle = [](const Vec3& x) { return x[0] * x[0] - x[1] * x[1]; };
const Field<2> Saddle2 = [](const Vec2& x) { return x[0] * x[0] - x[1] * x[1]; };

std::shared_ptr<const Boundary<3>> SphereBoundary()
{
  static const auto boundary =
    std::make_shared<const Boundary<3>>(MakeBoundary<3>(MakeIcosphere(4), { Saddle }));
  return boundary;
}

WalkSettings Laplace(double epsilon)
{
  WalkSettings settings;
  settings.Epsilon = epsilon;
  return settings;
}

// Bitwise equality of two batches' numbers.
void ExpectSameBits(const BatchEstimates& a, const BatchEstimates& b)
{
  ASSERT_EQ(a.Means.size(), b.Means.size());
  EXPECT_EQ(0, std::memcmp(a.Means.data(), b.Means.data(), a.Means.size() * sizeof(double)));
  EXPECT_EQ(
    0, std::memcmp(a.Variances.data(), b.Variances.data(), a.Variances.size() * sizeof(double)));
  for (std::size_t i = 0; i < a.Points; ++i)
  {
    EXPECT_EQ(a.Counters[i].Steps, b.Counters[i].Steps);
  }
}
} // namespace

TEST(Problem, BatchIsCalibratedIn3D)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-4));
  const auto points = RandomPointsInBall<3>(500, 0.85, 11);
  BatchRequest request;
  request.WalksPerPoint = 512;
  request.Seed = 3;
  const BatchEstimates estimates = problem.EstimateAll(AsProbe<3>(points), request);
  ASSERT_TRUE(estimates.Summary.Completed);
  EXPECT_EQ(estimates.Summary.WalksRun, 500u * 512u);
  EXPECT_EQ(estimates.Summary.Totals.Walks, 500u * 512u);
  Calibration c;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    ASSERT_TRUE(estimates.Finished[i]);
    const double z =
      (estimates.Value(i) - Saddle(points[i])) / std::sqrt(estimates.ValueVariance(i));
    c.MeanZ2 += z * z;
    c.MaxAbsZ = std::max(c.MaxAbsZ, std::abs(z));
    ++c.Points;
  }
  c.MeanZ2 /= c.Points;
  ExpectCalibrated(c);
}

TEST(Problem, GradientBatchIsCalibratedIn2D)
{
  const auto boundary =
    std::make_shared<const Boundary<2>>(MakeBoundary<2>(MakeCircle(512), { Saddle2 }));
  const Problem<2> problem(boundary, Laplace(1e-4));
  const auto points = RandomPointsInBall<2>(500, 0.8, 12);
  BatchRequest request;
  request.WalksPerPoint = 512;
  request.Derivatives.Gradient = true;
  request.Derivatives.ControlVariates = true;
  const BatchEstimates estimates = problem.EstimateAll(AsProbe<2>(points), request);
  const SampleLayout& layout = estimates.Summary.Layout;
  ASSERT_GE(layout.Gradient, 0);
  Calibration c;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Vec2 exact(2.0 * points[i][0], -2.0 * points[i][1]);
    for (int a = 0; a < 2; ++a)
    {
      const double z = (estimates.Mean(i, layout.Gradient + a) - exact[a]) /
        std::sqrt(estimates.Variance(i, layout.Gradient + a));
      c.MeanZ2 += z * z;
      c.MaxAbsZ = std::max(c.MaxAbsZ, std::abs(z));
      ++c.Points;
    }
  }
  c.MeanZ2 /= c.Points;
  ExpectCalibrated(c, 1000);
  EXPECT_EQ(estimates.Summary.StatusCounts[0], 500u);
}

TEST(Problem, SameBitsForAnyThreadCountAndSchedule)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-3));
  const auto many = AsProbe<3>(RandomPointsInBall<3>(40, 0.8, 13));
  const std::vector<std::array<double, 3>> one(many.begin(), many.begin() + 1);
  for (bool derivatives : { false, true })
  {
    BatchRequest request;
    request.WalksPerPoint = 700; // not a multiple of any block
    request.Derivatives.Gradient = derivatives;
    request.Threads = 1;
    const BatchEstimates serialMany = problem.EstimateAll(many, request);
    const BatchEstimates serialOne = problem.EstimateAll(one, request);
    request.Threads = 2;
    // 40 points: points over threads; 1 point: its walks in blocks over threads.
    ExpectSameBits(serialMany, problem.EstimateAll(many, request));
    ExpectSameBits(serialOne, problem.EstimateAll(one, request));
    // A point's numbers do not depend on the batch it is in.
    EXPECT_EQ(serialOne.Value(0), serialMany.Value(0));
  }
}

TEST(Problem, ResumedBatchEqualsOneBatch)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-3));
  // One point (its walks in blocks over the threads) and 30 (points over
  // the threads); legs that stop inside the derivative estimator's control
  // blocks of 256 walks and cross their boundaries.
  for (std::size_t count : { std::size_t(1), std::size_t(30) })
  {
    const auto points = AsProbe<3>(RandomPointsInBall<3>(static_cast<int>(count), 0.8, 14));
    for (bool derivatives : { false, true })
    {
      BatchRequest request;
      request.Derivatives.Gradient = derivatives;
      request.WalksPerPoint = 600;
      const BatchEstimates whole = problem.EstimateAll(points, request);

      RunningSumsCache kept;
      int before = 0;
      BatchEstimates resumed;
      for (int walks : { 100, 300, 520, 600 })
      {
        request.WalksPerPoint = walks;
        resumed = problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
        EXPECT_EQ(resumed.Summary.ResumedWalksPerPoint, before);
        EXPECT_EQ(resumed.Summary.WalksRun, count * static_cast<std::size_t>(walks - before));
        before = walks;
      }
      ExpectSameBits(whole, resumed);
    }
  }
}

TEST(Problem, ResumedTargetBatchEqualsOneBatch)
{
  // Target-error mode: a batch with a larger maximum continues the points
  // that had not reached the target (also those cut off between two checks,
  // at 150 walks) and keeps the others, as one batch with that maximum.
  const Problem<3> problem(SphereBoundary(), Laplace(1e-3));
  const auto points = AsProbe<3>(RandomPointsInBall<3>(30, 0.9, 16));
  for (bool derivatives : { false, true })
  {
    BatchRequest request;
    request.Derivatives.Gradient = derivatives;
    // A target half the points reach by 256 walks.
    request.WalksPerPoint = 256;
    const BatchEstimates fixed = problem.EstimateAll(points, request);
    std::vector<double> variances;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      variances.push_back(fixed.Variances[i * fixed.Variances.size() / points.size()]);
    }
    std::nth_element(variances.begin(), variances.begin() + 15, variances.end());
    request.TargetStandardError = std::sqrt(variances[15]);

    request.WalksPerPoint = 600;
    const BatchEstimates whole = problem.EstimateAll(points, request);
    int early = 0;
    int capped = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      early += whole.Counters[i].Walks < 256 ? 1 : 0;
      capped += whole.Counters[i].Walks == 600 ? 1 : 0;
    }
    EXPECT_GT(early, 0);
    EXPECT_LT(early + capped, 30); // some stop between the legs below

    RunningSumsCache kept;
    int before = 0;
    BatchEstimates resumed;
    for (int walks : { 150, 300, 600 })
    {
      request.WalksPerPoint = walks;
      resumed = problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
      EXPECT_EQ(resumed.Summary.ResumedWalksPerPoint, before);
      before = walks;
    }
    ExpectSameBits(whole, resumed);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      EXPECT_EQ(whole.Counters[i].Walks, resumed.Counters[i].Walks);
    }
  }
}

TEST(Problem, ProgressCallbackAborts)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-4));
  const auto points = AsProbe<3>(RandomPointsInBall<3>(2000, 0.8, 15));
  BatchRequest request;
  request.WalksPerPoint = 100000;
  int calls = 0;
  RunningSumsCache kept;
  const BatchEstimates estimates = problem.EstimateAll(points, request,
    [&calls](const BatchProgress& p) {
      EXPECT_GE(p.Fraction, 0.0);
      EXPECT_LE(p.Fraction, 1.0);
      return ++calls < 2;
    },
    &kept);
  EXPECT_FALSE(estimates.Summary.Completed);
  EXPECT_EQ(calls, 2);
  std::size_t finished = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    finished += estimates.Finished[i];
    if (!estimates.Finished[i])
    {
      EXPECT_TRUE(std::isnan(estimates.Value(i)));
    }
  }
  EXPECT_LT(finished, points.size());
  EXPECT_LT(estimates.Summary.WalksRun, points.size() * 100000u);
  // An aborted batch keeps what it ran, and hands every point that holds
  // walks to the sink: here those it started.
  EXPECT_FALSE(kept.Uniform());
  EXPECT_TRUE(kept.Interrupted());
  EXPECT_GT(kept.KeptWalks(), 0u);
  EXPECT_LT(estimates.Summary.PointsFinished, finished);
  EXPECT_EQ(estimates.Summary.PointsWithoutWalks, points.size() - finished);
}

// An aborted batch, continued with the same request, gives the bits of one
// batch: the points it finished, those it cut short between chunks and
// those it never reached (fresh, or with the walks of an earlier batch)
// each continue from their own count. One point (its walks in blocks over
// the threads) and 20 (points over the threads), values and gradients.
TEST(Problem, AbortedBatchContinuesToOneBatch)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-3));
  for (std::size_t count : { std::size_t(1), std::size_t(20) })
  {
    const auto points = AsProbe<3>(RandomPointsInBall<3>(static_cast<int>(count), 0.8, 17));
    for (bool derivatives : { false, true })
    {
      if (count == 1 && derivatives)
      {
        continue; // the blocks' history is covered by ResumedBatchEqualsOneBatch
      }
      BatchRequest request;
      request.Threads = 2;
      request.Derivatives.Gradient = derivatives;
      RunningSumsCache kept;
      request.WalksPerPoint = 300; // an earlier, complete batch
      problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
      // Enough walks that the first progress report (after 0.1 s) comes
      // before the end; more if this machine was faster.
      BatchEstimates aborted;
      int walks = count == 1 ? 60000 : 2500;
      for (int attempt = 0; attempt < 4; ++attempt, walks *= 4)
      {
        request.WalksPerPoint = walks;
        aborted = problem.EstimateAll(
          points, request, [](const BatchProgress&) { return false; }, &kept);
        if (!aborted.Summary.Completed)
        {
          break;
        }
      }
      ASSERT_FALSE(aborted.Summary.Completed);
      // Every point holds walks (at least the earlier batch's 300), so
      // every point is in the aborted output, none NaN.
      EXPECT_EQ(aborted.Summary.PointsWithoutWalks, 0u);
      EXPECT_EQ(aborted.Summary.ResumedWalksPerPoint, 300);
      std::size_t fewer = 0;
      for (std::size_t i = 0; i < count; ++i)
      {
        EXPECT_EQ(aborted.Finished[i], 1);
        EXPECT_FALSE(std::isnan(aborted.Value(i)));
        EXPECT_GE(aborted.Counters[i].Walks, 300u);
        fewer += aborted.Counters[i].Walks < static_cast<std::uint64_t>(walks) ? 1 : 0;
      }
      EXPECT_GT(fewer, 0u);
      EXPECT_EQ(aborted.Summary.PointsFinished, count - fewer);

      const BatchEstimates continued =
        problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
      EXPECT_TRUE(continued.Summary.Completed);
      const BatchEstimates whole = problem.EstimateAll(points, request);
      ExpectSameBits(whole, continued);
    }
  }
}

// A target changed after a target batch: a tighter one continues from the
// kept walks (stopped points checked again), a fixed count continues every
// point to it, and both give the bits of one batch of the new request; a
// looser target starts afresh.
TEST(Problem, TargetChangeContinuesWhereItCan)
{
  const Problem<3> problem(SphereBoundary(), Laplace(1e-3));
  const auto points = AsProbe<3>(RandomPointsInBall<3>(30, 0.9, 16));
  BatchRequest request;
  request.WalksPerPoint = 256;
  const BatchEstimates fixed = problem.EstimateAll(points, request);
  std::vector<double> variances;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    variances.push_back(fixed.ValueVariance(i));
  }
  std::sort(variances.begin(), variances.end());
  const double loose = std::sqrt(variances[20]);
  const double tight = std::sqrt(variances[8]);
  request.WalksPerPoint = 1024;

  RunningSumsCache kept;
  request.TargetStandardError = loose;
  const BatchEstimates first = problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
  request.TargetStandardError = tight;
  const BatchEstimates tighter =
    problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
  EXPECT_GT(tighter.Summary.ResumedWalksPerPoint, 0);
  EXPECT_LT(tighter.Summary.WalksRun, problem.EstimateAll(points, request).Summary.WalksRun);
  ExpectSameBits(problem.EstimateAll(points, request), tighter);
  int more = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    more += tighter.Counters[i].Walks > first.Counters[i].Walks ? 1 : 0;
  }
  EXPECT_GT(more, 0);

  request.TargetStandardError = 0.0;
  const BatchEstimates toFixed =
    problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
  EXPECT_GT(toFixed.Summary.ResumedWalksPerPoint, 0);
  ExpectSameBits(problem.EstimateAll(points, request), toFixed);

  request.TargetStandardError = tight;
  problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
  request.TargetStandardError = loose;
  const BatchEstimates looser =
    problem.EstimateAll(points, request, BatchProgressCallback(), &kept);
  EXPECT_EQ(looser.Summary.ResumedWalksPerPoint, 0);
  ExpectSameBits(first, looser);
}

// Walk on stars through the problem: a mixed 3D problem's batch is calibrated, and
// gives the same bits on 1 and 2 threads, with points spread over threads
// (many points) and with one point's walks spread in blocks (one point),
// values and derivatives.
TEST(Problem, WalkOnStarsBatchesAreCalibratedAndThreadIndependent)
{
  const Shape<3> l = LPrism();
  auto mixed = std::make_shared<const MixedBoundary<3>>(MakeMixed<3>(l.Mesh, LPrismDirichlet, LPrismSolution, LPrismGradient));
  const Problem<3> problem(mixed, Laplace(1e-4));
  EXPECT_EQ(problem.GetMixedBoundary(), mixed.get());
  const auto points = PointsInside(l, 200, 6);
  const auto probe = AsProbe<3>(points);
  BatchRequest request;
  request.Seed = 11;
  // Runs on two threads and on one; both must give the same bits.
  auto onTwoAndOneThreads = [&](const std::vector<std::array<double, 3>>& at, int walks) {
    request.WalksPerPoint = walks;
    request.Threads = 2;
    const BatchEstimates two = problem.EstimateAll(at, request);
    request.Threads = 1;
    const BatchEstimates one = problem.EstimateAll(at, request);
    EXPECT_EQ(one.Means, two.Means);
    EXPECT_EQ(one.Variances, two.Variances);
    return two;
  };
  const BatchEstimates two = onTwoAndOneThreads(probe, 128);
  Calibration c;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double z = (two.Value(i) - LPrismSolution(points[i])) / std::sqrt(two.ValueVariance(i));
    c.MeanZ2 += z * z / points.size();
    c.MaxAbsZ = std::max(c.MaxAbsZ, std::abs(z));
    ++c.Points;
  }
  ExpectCalibrated(c, 200);

  const std::vector<std::array<double, 3>> single(probe.begin(), probe.begin() + 1);
  onTwoAndOneThreads(single, 640);

  // Derivative batches (a first ball, then walks on stars): the same bits
  // too, one point's walks crossing control blocks; the gradient near ∇u.
  request.Derivatives.Gradient = true;
  const SampleLayout layout = problem.Layout(request);
  ASSERT_GE(layout.Gradient, 0);
  EXPECT_EQ(layout.Weight, -1);
  const BatchEstimates derivatives = onTwoAndOneThreads(single, 640);
  const Vec3 exact = LPrismGradient(points[0]);
  for (int k = 0; k < 3; ++k)
  {
    const std::size_t at = static_cast<std::size_t>(layout.Gradient + k);
    EXPECT_LT(std::abs(derivatives.Means[at] - exact[k]), 5.0 * std::sqrt(derivatives.Variances[at]));
  }
  WalkSettings biharmonic = Laplace(1e-4);
  biharmonic.Problem = Equation::Biharmonic;
  EXPECT_THROW(Problem<3>(mixed, biharmonic), std::invalid_argument);
}

TEST(Problem, RefusesProblemsNoWalkCanSolve)
{
  EXPECT_THROW(Problem<3>(std::shared_ptr<const Boundary<3>>(), Laplace(1e-3)), std::invalid_argument);
  EXPECT_THROW(Problem<3>(std::make_shared<const Boundary<3>>(), Laplace(1e-3)),
    std::invalid_argument);
  EXPECT_THROW(Problem<3>(SphereBoundary(), Laplace(0.0)), std::invalid_argument);
  WalkSettings screened = Laplace(1e-3);
  screened.Problem = Equation::ScreenedPoisson;
  EXPECT_THROW(Problem<3>(SphereBoundary(), screened), std::invalid_argument);
  WalkSettings biharmonic = Laplace(1e-3);
  biharmonic.Problem = Equation::Biharmonic; // one component, not g and h
  EXPECT_THROW(Problem<3>(SphereBoundary(), biharmonic), std::invalid_argument);
}
