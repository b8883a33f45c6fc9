// ThreadSanitizer tests of the core's thread-safety contract: one Boundary (its
// BVH and values), volume and concentrated sources are shared read-only by
// every thread, each thread builds its own estimator, and the estimates do not
// depend on the thread that computes them.
//
// The threads here are std::threads, not TBB's: Debian's libtbb is not built
// with -fsanitize=thread, so TSan does not see how TBB hands a task from one
// thread to another and reports the data of any TBB-parallel loop as racing
// (see Documentation/draft-sanitizers.md). std::thread's start and join are
// seen, so every report here is a real race. ParallelForWithProgress runs on
// one TBB thread: its own protocol (worker thread, progress polling on the
// calling thread, abort flag, exception hand-off) is checked, not TBB's.
#include <gridfree/boundary/Boundary.h>
#include <gridfree/sources/ConcentratedSources.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// Runs estimate(begin, end) over [0, count) on `threads` std::threads, each
// with a contiguous block, as ParallelForWithProgress splits a probe.
void RunOnThreads(std::size_t count, int threads,
  const std::function<void(std::size_t, std::size_t)>& estimate)
{
  std::vector<std::thread> pool;
  const std::size_t block = (count + threads - 1) / threads;
  for (int t = 0; t < threads; ++t)
  {
    const std::size_t begin = std::min(count, t * block);
    const std::size_t end = std::min(count, begin + block);
    pool.emplace_back(estimate, begin, end);
  }
  for (std::thread& thread : pool)
  {
    thread.join();
  }
}

template <int DIM>
std::vector<double> Solve(const Boundary<DIM>& boundary, const WalkSettings& settings,
  const std::vector<Vec<DIM>>& points, int threads, VolumeSource<DIM>* volume = nullptr,
  const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>())
{
  const int components = WalkOnSpheresEstimator<DIM>(boundary, settings, volume, concentrated)
                           .OutputComponents();
  std::vector<double> result(points.size() * components * 2);
  RunOnThreads(points.size(), threads, [&](std::size_t begin, std::size_t end) {
    WalkOnSpheresEstimator<DIM> estimator(boundary, settings, volume, concentrated);
    RunningStatistics stats(components);
    for (std::size_t i = begin; i < end; ++i)
    {
      double xyz[3] = { 0, 0, 0 };
      for (int k = 0; k < DIM; ++k)
      {
        xyz[k] = points[i][k];
      }
      stats.Reset();
      WalkCounters counters;
      estimator.EstimatePoint(xyz, 21, 0, 16, stats, counters);
      for (int c = 0; c < components; ++c)
      {
        result[(i * components + c) * 2] = stats.GetMean(c);
        result[(i * components + c) * 2 + 1] = stats.VarianceOfMean(c);
      }
    }
  });
  return result;
}

template <int DIM>
std::vector<double> SolveDerivatives(const Boundary<DIM>& boundary, const WalkSettings& settings,
  const DerivativeRequest& request, const std::vector<Vec<DIM>>& points, int threads,
  VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
{
  const int size =
    DerivativeWalkOnSpheres<DIM>(boundary, settings, request, volume, concentrated).Layout().Size;
  std::vector<double> result(points.size() * size);
  RunOnThreads(points.size(), threads, [&](std::size_t begin, std::size_t end) {
    DerivativeWalkOnSpheres<DIM> estimator(boundary, settings, request, volume, concentrated);
    RunningStatistics stats(size);
    for (std::size_t i = begin; i < end; ++i)
    {
      double xyz[3] = { 0, 0, 0 };
      for (int k = 0; k < DIM; ++k)
      {
        xyz[k] = points[i][k];
      }
      stats.Reset();
      WalkCounters counters;
      estimator.EstimatePoint(xyz, 5, 0, 40, stats, counters);
      for (int c = 0; c < size; ++c)
      {
        result[i * size + c] = stats.GetMean(c);
      }
    }
  });
  return result;
}

WalkSettings Settings(Equation equation, int dim)
{
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(double(dim));
  s.Problem = equation;
  return s;
}
} // namespace

// A mesh boundary (BVH, per-vertex values) shared by three threads.
TEST(ThreadSafety, LaplaceOnASharedMesh)
{
  const SimplexMesh<3> sphere = MakeIcosphere(3);
  const Boundary<3> boundary = MakeBoundary<3>(sphere,
    std::vector<Field<3>>{ [](const Vec3& x) { return x[0] * x[1] + x[2]; } });
  const auto points = RandomPointsInBall<3>(60, 0.9, 3);
  const WalkSettings settings = Settings(Equation::Laplace, 3);
  EXPECT_EQ(Solve<3>(boundary, settings, points, 1), Solve<3>(boundary, settings, points, 3));
}

// A stateless volume source (thread-local scratch) and point sources (per-thread
// buffers of the ball queries) shared by two threads, through the Poisson
// walk and the derivative estimator with control variates.
TEST(ThreadSafety, PoissonWithSharedSources)
{
  const Boundary<2> boundary = MakeBoundary<2>(
    UnitSphereMesh<2>(), std::vector<Field<2>>{ [](const Vec2& x) { return x[0] - x[1]; } });
  FunctionSource<2> volume([](const Vec2& x) { return 1.0 + x[0] * x[0]; });
  std::vector<Vec2> centres = { Vec2(0.3, 0.2), Vec2(-0.35, -0.1) };
  PointSources<2> sources;
  sources.Set(centres, 1, { 1.5, -0.8 });
  ConcentratedSourceSet<2> concentrated;
  concentrated.Points = &sources;
  const auto points = RandomPointsInBall<2>(40, 0.85, 7);
  const WalkSettings settings = Settings(Equation::Poisson, 2);
  EXPECT_EQ(Solve<2>(boundary, settings, points, 1, &volume, concentrated),
    Solve<2>(boundary, settings, points, 2, &volume, concentrated));

  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  EXPECT_EQ(SolveDerivatives<2>(boundary, settings, request, points, 1, &volume, concentrated),
    SolveDerivatives<2>(boundary, settings, request, points, 2, &volume, concentrated));
}

// Biharmonic tree walks (two coupled components) on two threads.
TEST(ThreadSafety, BiharmonicTreeWalks)
{
  const Boundary<2> boundary = MakeBoundary<2>(UnitSphereMesh<2>(),
    std::vector<Field<2>>{
      [](const Vec2& x) { return x.squaredNorm() * x[0]; }, [](const Vec2& x) { return 8.0 * x[0]; } });
  WalkSettings settings = Settings(Equation::Biharmonic, 2);
  settings.Biharmonic = BiharmonicStrategy::TreeWalking;
  const auto points = RandomPointsInBall<2>(30, 0.85, 11);
  EXPECT_EQ(Solve<2>(boundary, settings, points, 1), Solve<2>(boundary, settings, points, 2));
}

// ParallelForWithProgress's own threads: the worker std::thread runs the loop
// while the calling thread polls progress.
TEST(ThreadSafety, ParallelLoopProtocol)
{
  std::vector<int> visits(5000, 0);
  int reports = 0;
  EXPECT_TRUE(ParallelForWithProgress(visits.size(), 1,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      for (std::size_t i = begin; i < end; ++i)
      {
        ++visits[i];
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
    },
    [&](double fraction) {
      EXPECT_LE(fraction, 1.0);
      ++reports;
      return true;
    },
    0.01));
  EXPECT_GT(reports, 0);
  for (int v : visits)
  {
    ASSERT_EQ(v, 1);
  }

  std::size_t processed = 0;
  EXPECT_FALSE(ParallelForWithProgress(100000, 1,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
      for (std::size_t i = begin; i < end && !cancel; ++i)
      {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        ++processed;
      }
    },
    [&](double) { return false; }, 0.01));
  EXPECT_LT(processed, 100000u);

  EXPECT_THROW(ParallelForWithProgress(100, 1,
                 [](std::size_t, std::size_t, const std::atomic<bool>&) {
                   throw std::runtime_error("boom");
                 },
                 [](double) { return true; }, 0.001),
    std::runtime_error);
}
