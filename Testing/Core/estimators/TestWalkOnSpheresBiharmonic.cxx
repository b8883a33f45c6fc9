// Statistical tests of the biharmonic estimators (paper Sec. 2.5 and 4.3):
// Δ²u = 0 with u = g and Δu = h on the boundary, for u = x|x|² (so
// Δu = 2(n+2)x, DESIGN.md §3), in 2D and 3D, by tree walking and by nested
// walks. Both u and the by-product Δu are checked.
#include "EstimatorChecks.h"

#include <gtest/gtest.h>

#include <chrono>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
constexpr int Points = 400;

template <int DIM>
Field<DIM> U()
{
  return [](const Vec<DIM>& x) { return x[0] * x.squaredNorm(); };
}

template <int DIM>
Field<DIM> LaplacianU()
{
  return [](const Vec<DIM>& x) { return 2.0 * (DIM + 2) * x[0]; };
}

template <int DIM>
WalkSettings Biharmonic(BiharmonicStrategy strategy, int nestedWalks = 1)
{
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  s.Problem = Equation::Biharmonic;
  s.Biharmonic = strategy;
  s.NestedWalks = nestedWalks;
  return s;
}

template <int DIM>
void CheckBiharmonic(
  BiharmonicStrategy strategy, int walks, std::uint64_t seed, int count = Points)
{
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { U<DIM>(), LaplacianU<DIM>() });
  const auto points = RandomPointsInBall<DIM>(count, 0.85, 70 + DIM);
  const auto result = CheckEstimator<DIM>(boundary, Biharmonic<DIM>(strategy), points,
    { U<DIM>(), LaplacianU<DIM>() }, walks, seed);
  ExpectCalibrated(result[0], count); // u
  ExpectCalibrated(result[1], count); // Δu
}
} // namespace

TEST(BiharmonicWalkOnSpheres3D, TreeWalking)
{
  CheckBiharmonic<3>(BiharmonicStrategy::TreeWalking, 512, 500);
}

TEST(BiharmonicWalkOnSpheres2D, TreeWalking)
{
  CheckBiharmonic<2>(BiharmonicStrategy::TreeWalking, 512, 501);
}

TEST(BiharmonicWalkOnSpheres3D, Nested)
{
  CheckBiharmonic<3>(BiharmonicStrategy::Nested, 256, 502, 200);
}

TEST(BiharmonicWalkOnSpheres2D, Nested)
{
  CheckBiharmonic<2>(BiharmonicStrategy::Nested, 256, 503);
}

// Leaving out the Laplacian term (solving Δu = 0 with u = g) must fail.
TEST(BiharmonicWalkOnSpheres3D, CheckRejectsTheHarmonicSolution)
{
  const Boundary<3> boundary = MakeBoundary<3>(UnitSphereMesh<3>(), { U<3>() });
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(3.0);
  const auto points = RandomPointsInBall<3>(Points, 0.85, 73);
  EXPECT_GT(CheckEstimator<3>(boundary, s, points, { U<3>() }, 256, 504)[0].MaxAbsZ, 5.0);
}

TEST(BiharmonicWalkOnSpheres, RejectsOddComponentCount)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(1), { U<3>() });
  EXPECT_THROW(
    WalkOnSpheresEstimator<3>(boundary, Biharmonic<3>(BiharmonicStrategy::TreeWalking)),
    std::invalid_argument);
}

// Paper Fig. 11: at equal compute time, tree walking has a lower error than
// the nested estimator. Prints the measured figures.
TEST(BiharmonicWalkOnSpheres3D, TreeWalkingBeatsNestedAtEqualTime)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { U<3>(), LaplacianU<3>() });
  const auto points = RandomPointsInBall<3>(100, 0.8, 74);
  auto run = [&](BiharmonicStrategy strategy, int walks, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    WalkOnSpheresEstimator<3> estimator(boundary, Biharmonic<3>(strategy));
    RunningStatistics stats(2);
    double squaredError = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const double xyz[3] = { points[i][0], points[i][1], points[i][2] };
      stats.Reset();
      WalkCounters counters;
      estimator.EstimatePoint(xyz, 600, 0, walks, stats, counters);
      const double e = stats.GetMean(0) - U<3>()(points[i]);
      squaredError += e * e;
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::sqrt(squaredError / points.size());
  };
  double treeSeconds = 0.0, nestedSeconds = 0.0;
  const int treeWalks = 256;
  const double treeError = run(BiharmonicStrategy::TreeWalking, treeWalks, treeSeconds);
  // Nested walks cost about (1 + steps) Laplace walks each: match the time.
  double probeSeconds = 0.0;
  run(BiharmonicStrategy::Nested, 16, probeSeconds);
  const int nestedWalks = std::max(2, int(16 * treeSeconds / probeSeconds));
  const double nestedError = run(BiharmonicStrategy::Nested, nestedWalks, nestedSeconds);
  std::printf("biharmonic at equal time: tree walking %d walks %.3f s RMS error %.4g; nested %d "
              "walks %.3f s RMS error %.4g; error ratio nested/tree %.2f\n",
    treeWalks, treeSeconds, treeError, nestedWalks, nestedSeconds, nestedError,
    nestedError / treeError);
  EXPECT_LT(treeError, nestedError);
}
