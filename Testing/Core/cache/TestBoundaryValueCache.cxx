// Tests of gridfree/cache/BoundaryValueCache.h: every probe point answered
// by the representation formula over one cache of boundary walks agrees
// with the exact solution within its own error bar, the error bars are
// calibrated over independent caches (points of one cache share it, so the
// calibration pools several), the answer has the same bits for any thread
// count, and points in the shell or outside are left to pointwise walks.
#include <gridfree/cache/BoundaryValueCache.h>
#include "BlockShapes.h"
#include "CacheChecks.h"
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// Answers at `points` from `caches` independent caches (seeds from
// `firstSeed`), pooled against the exact u and ∇u; points in the shell are
// skipped (none may be outside). Returns the points answered per cache.
template <int DIM>
std::size_t PoolCaches(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& points,
  int caches, std::uint64_t firstSeed, const Field<DIM>& u,
  const std::function<Vec<DIM>(const Vec<DIM>&)>& gradient, CachePooled& values,
  CachePooled& gradients)
{
  std::size_t answered = 0;
  for (int k = 0; k < caches; ++k)
  {
    BoundaryCacheSettings settings;
    settings.CachePoints = 2048;
    settings.WalksPerCachePoint = 32;
    settings.Seed = firstSeed + static_cast<std::uint64_t>(k);
    const BoundaryValueCache<DIM> cache(problem, settings);
    EXPECT_TRUE(cache.Complete());
    CacheEvaluation answer;
    cache.Evaluate(points, true, answer);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      EXPECT_FALSE(answer.Outside[i]) << i;
    }
    const std::size_t count = PoolAnswers<DIM>(answer, points, u, gradient, values, gradients);
    answered = k == 0 ? count : answered;
  }
  return answered;
}

template <int DIM>
void ExpectCalibratedCaches(
  const SimplexMesh<DIM>& mesh, double probeRadius, int caches, const CacheCase<DIM>& with = {})
{
  const auto boundary = std::make_shared<const Boundary<DIM>>(MakeBoundary<DIM>(mesh, { with.U }));
  WalkSettings walk = CacheLaplace();
  walk.Problem = with.Kind;
  walk.ScreeningCoefficient = with.Screening;
  std::shared_ptr<SourceSet<DIM>> sources;
  if (with.F)
  {
    sources = std::make_shared<SourceSet<DIM>>();
    const Field<DIM> f = with.F;
    sources->MakeVolume = [f](double) { return std::make_unique<FunctionSource<DIM>>(f); };
  }
  const Problem<DIM> problem(boundary, walk, sources);
  const auto points = CacheProbe<DIM>(40, probeRadius);
  CachePooled values, gradients;
  EXPECT_EQ(PoolCaches<DIM>(problem, points, caches, 100, with.U, with.Gradient, values, gradients),
    points.size());
  ExpectPooledCalibrated(values, gradients);
}
} // namespace

TEST(BoundaryValueCache, CalibratedInTheBall)
{
  ExpectCalibratedCaches<3>(MakeIcosphere(4), 0.8, 12);
}

// In 2D the error bars come out about 10–15% wide (mean z² 0.83–0.85 over
// 48 caches): the pooled figure needs many caches to settle.
TEST(BoundaryValueCache, CalibratedInTheDisc)
{
  ExpectCalibratedCaches<2>(MakeCircle(1024), 0.85, 48);
}


TEST(BoundaryValueCache, PoissonCalibrated)
{
  ExpectCalibratedCaches<3>(MakeIcosphere(4), 0.8, 12, CachePoisson<3>());
  ExpectCalibratedCaches<2>(MakeCircle(1024), 0.85, 24, CachePoisson<2>());
}

TEST(BoundaryValueCache, ScreenedPoissonCalibrated)
{
  ExpectCalibratedCaches<3>(MakeIcosphere(4), 0.8, 12, CacheScreened<3>());
  ExpectCalibratedCaches<2>(MakeCircle(1024), 0.85, 24, CacheScreened<2>());
}

// The same bits for one thread and two; the shell and the outside are
// flagged, not answered; what the cache cannot answer is refused.
TEST(BoundaryValueCache, ThreadsShellOutsideAndRefusals)
{
  const auto boundary =
    std::make_shared<const Boundary<3>>(MakeBoundary<3>(MakeIcosphere(3), { CacheSaddle<3> }));
  const Problem<3> problem(boundary, CacheLaplace());
  const std::vector<std::array<double, 3>> points = { { 0.1, 0.2, 0.3 }, { 0.0, 0.0, 0.97 },
    { 2.0, 0.0, 0.0 }, { 0.5, -0.2, 0.1 }, { 0.0, 0.0, 1.02 } };
  CacheEvaluation one, two;
  for (int threads : { 1, 2 })
  {
    BoundaryCacheSettings settings;
    settings.CachePoints = 256;
    settings.WalksPerCachePoint = 16;
    settings.Threads = threads;
    const BoundaryValueCache<3> cache(problem, settings);
    cache.Evaluate(points, true, threads == 1 ? one : two);
  }
  ASSERT_EQ(one.Value.size(), two.Value.size());
  EXPECT_EQ(0, std::memcmp(one.Value.data(), two.Value.data(), one.Value.size() * sizeof(double)));
  EXPECT_EQ(0,
    std::memcmp(one.Gradient.data(), two.Gradient.data(), one.Gradient.size() * sizeof(double)));
  // (Outside comes first: a point outside within the shell's distance is
  // outside.)
  EXPECT_EQ(one.InShell, (std::vector<unsigned char>{ 0, 1, 0, 0, 0 }));
  EXPECT_EQ(one.Outside, (std::vector<unsigned char>{ 0, 0, 1, 0, 1 }));
  EXPECT_TRUE(std::isfinite(one.Value[0]));
  EXPECT_TRUE(std::isnan(one.Value[1]));
  EXPECT_TRUE(std::isnan(one.Value[2]));

  const Field<3> zero = [](const Vec3&) { return 0.0; };
  const auto twoValues = std::make_shared<const Boundary<3>>(
    MakeBoundary<3>(MakeIcosphere(3), { CacheSaddle<3>, zero }));
  WalkSettings biharmonic = CacheLaplace();
  biharmonic.Problem = Equation::Biharmonic;
  const Problem<3> plate(twoValues, biharmonic);
  EXPECT_THROW(BoundaryValueCache<3>(plate, BoundaryCacheSettings()), std::invalid_argument);
}

// A screened Poisson cache with a source, in 3D and 2D: the same bits for
// one thread and two, every answer finite.
template <int DIM>
void ExpectThreadIndependentScreened(const SimplexMesh<DIM>& mesh)
{
  const CacheCase<DIM> with = CacheScreened<DIM>();
  const auto boundary = std::make_shared<const Boundary<DIM>>(MakeBoundary<DIM>(mesh, { with.U }));
  WalkSettings walk = CacheLaplace();
  walk.Problem = with.Kind;
  walk.ScreeningCoefficient = with.Screening;
  auto sources = std::make_shared<SourceSet<DIM>>();
  const Field<DIM> f = with.F;
  sources->MakeVolume = [f](double) { return std::make_unique<FunctionSource<DIM>>(f); };
  const Problem<DIM> problem(boundary, walk, sources);
  const auto points = CacheProbe<DIM>(6, 0.7);
  CacheEvaluation one, two;
  for (int threads : { 1, 2 })
  {
    BoundaryCacheSettings settings;
    settings.CachePoints = 128;
    settings.VolumePoints = 256;
    settings.WalksPerCachePoint = 8;
    settings.Threads = threads;
    const BoundaryValueCache<DIM> cache(problem, settings);
    cache.Evaluate(points, true, threads == 1 ? one : two);
  }
  ASSERT_EQ(one.Value.size(), points.size());
  EXPECT_EQ(0, std::memcmp(one.Value.data(), two.Value.data(), one.Value.size() * sizeof(double)));
  EXPECT_EQ(0,
    std::memcmp(one.Gradient.data(), two.Gradient.data(), one.Gradient.size() * sizeof(double)));
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    EXPECT_TRUE(std::isfinite(one.Value[i]) && std::isfinite(one.ValueVariance[i])) << i;
  }
}

// Refine continues the kept walks: a cache of 4 walks per point refined to
// 8 has the bits of one built with 8, and answers the same.
template <int DIM>
void ExpectRefineContinues(const SimplexMesh<DIM>& mesh)
{
  const CacheCase<DIM> with = CacheScreened<DIM>();
  const auto boundary = std::make_shared<const Boundary<DIM>>(MakeBoundary<DIM>(mesh, { with.U }));
  WalkSettings walk = CacheLaplace();
  walk.Problem = with.Kind;
  walk.ScreeningCoefficient = with.Screening;
  const Problem<DIM> problem(boundary, walk);
  BoundaryCacheSettings settings;
  settings.CachePoints = 64;
  settings.WalksPerCachePoint = 8;
  const BoundaryValueCache<DIM> whole(problem, settings);
  settings.WalksPerCachePoint = 4;
  BoundaryValueCache<DIM> grown(problem, settings);
  EXPECT_EQ(grown.WalksPerCachePoint(), 4);
  EXPECT_TRUE(grown.Refine(problem, 8));
  EXPECT_EQ(grown.WalksPerCachePoint(), 8);
  EXPECT_EQ(grown.Walks(), 64u * 4u); // only the missing walks ran
  EXPECT_EQ(0, std::memcmp(whole.CacheNormalDerivatives().data(),
                 grown.CacheNormalDerivatives().data(),
                 whole.CacheNormalDerivatives().size() * sizeof(double)));
  EXPECT_TRUE(grown.Refine(problem, 6)); // fewer: nothing runs, nothing changes
  EXPECT_EQ(grown.WalksPerCachePoint(), 8);
}

TEST(BoundaryValueCache, SourcesAndScreeningAreThreadIndependent)
{
  ExpectRefineContinues<3>(MakeIcosphere(2));
  ExpectRefineContinues<2>(MakeCircle(128));
  ExpectThreadIndependentScreened<3>(MakeIcosphere(3));
  ExpectThreadIndependentScreened<2>(MakeCircle(256));
}

// A shape none of the tests above used, with a reflex edge (corner): the
// L of three unit cells, the points of a grid inside it that are clear of
// the shell, over independent caches.
template <int DIM>
void ExpectCalibratedInTheL(int caches)
{
  const auto boundary = std::make_shared<const Boundary<DIM>>(
    MakeBoundary<DIM>(MakeCacheL<DIM>(), { CacheSaddle<DIM> }));
  const Problem<DIM> problem(boundary, CacheLaplace());
  const std::vector<std::array<double, 3>> points = CacheLGrid(0.1, 0.225, 1.0);
  CachePooled values, gradients;
  const std::size_t answered = PoolCaches<DIM>(problem, points, caches, 300, CacheSaddle<DIM>,
    CacheSaddleGradient<DIM>, values, gradients);
  EXPECT_GE(answered, 20u);
  ExpectPooledCalibrated(values, gradients);
}

TEST(BoundaryValueCache, CalibratedInTheL)
{
  ExpectCalibratedInTheL<3>(12);
  ExpectCalibratedInTheL<2>(48);
}
