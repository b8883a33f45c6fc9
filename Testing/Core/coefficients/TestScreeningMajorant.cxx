// Tests of gridfree/coefficients/ScreeningMajorant.h: the bound grid's σ̄
// for a ball bounds σ′ from above and 4|σ′| where σ′ < 0, its floor σ_c lies
// below σ′ and σ′ and the source f′ keep to their reported ranges (and f′ to
// the reported largest |f′|), at points sampled densely in
// the ball, for balls of every size; it is tight where the coefficients
// are flat (far below the global bound away from a steep step) and exactly 0
// where σ′ vanishes; bad boxes and non-finite coefficients are refused.
#include <gridfree/coefficients/ScreeningMajorant.h>
#include "EstimatorChecks.h"
#include "ManufacturedCoefficients.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
ManufacturedCase<2> SteepStep()
{
  ManufacturedCase<2> with;
  with.U = SineSolution<2>();
  with.Alpha = SmoothStep<2>(5.5, 4.5, 0.0, 0.05);
  with.Sigma = [](const Vec<2>& x) { return 1.0 + x[1] * x[1]; };
  return with;
}
} // namespace

TEST(ScreeningMajorant, BoundsEveryBallOfTheGrid)
{
  const ManufacturedField<2> field(SteepStep());
  const ScreeningBoundGrid<2> grid(field, Vec<2>(-1, -1), Vec<2>(1, 1), {});
  EXPECT_EQ(grid.LevelCount(), 6); // 32, 16, 8, 4, 2, 1 cells per axis
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (double radius : { 0.003, 0.02, 0.1, 0.4, 1.0 })
  {
    for (int b = 0; b < 40; ++b)
    {
      const Vec<2> center(unit(rng), unit(rng));
      const BallScreening bound = grid.ForBall(center, radius);
      EXPECT_GE(bound.Floor, 0.0);
      EXPECT_LT(bound.Floor, bound.Bound);
      for (const Vec<2>& d : RandomPointsInBall<2>(200, radius, 100 + b))
      {
        const Vec<2> y = center + d;
        if (y.cwiseAbs().maxCoeff() > 1.0)
        {
          continue;
        }
        CoefficientSample<2> c;
        field.Evaluate(y, c);
        const double s = Transform(c).Screening;
        EXPECT_GE(bound.Bound, s);
        EXPECT_GE(bound.Bound, -4.0 * s);
        EXPECT_LE(bound.Floor, std::max(s, 0.0));
        EXPECT_LE(bound.Lowest, s);
        EXPECT_GE(bound.Highest, s);
        // The source's range, which the walk's source roulette centres on.
        const double f = Transform(c).Source;
        EXPECT_LE(bound.SourceLowest, f);
        EXPECT_GE(bound.SourceHighest, f);
        EXPECT_GE(bound.SourceScale, std::abs(f));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 20000);
}

TEST(ScreeningMajorant, TightAwayFromTheStep)
{
  const ManufacturedField<2> field(SteepStep());
  const ScreeningBoundGrid<2> grid(field, Vec<2>(-1, -1), Vec<2>(1, 1), {});
  const BallScreening global = grid.ForBall(Vec<2>(0, 0), 2.0);
  // Far from x = 0, α ≈ 10 is flat and σ′ ≈ σ/10 ∈ [0.1, 0.2]: the floor
  // takes most of it.
  const BallScreening flat = grid.ForBall(Vec<2>(0.8, 0.0), 0.1);
  EXPECT_LT(flat.Bound, 0.3);
  EXPECT_GT(flat.Floor, 0.5 * flat.Bound);
  EXPECT_GT(global.Bound, 100.0 * flat.Bound);
  // The step makes σ′ negative somewhere in the whole box: no floor.
  EXPECT_EQ(global.Floor, 0.0);
}

TEST(ScreeningMajorant, ZeroWhereNothingScreens)
{
  const CallableCoefficients<3> field(
    [](const Vec<3>&, CoefficientSample<3>& out) { out.Alpha = 3.0; });
  const ScreeningBoundGrid<3> grid(field, Vec<3>(0, 0, 0), Vec<3>(1, 2, 3), {});
  EXPECT_EQ(grid.ForBall(Vec<3>(0.5, 1.0, 1.5), 0.2).Bound, 0.0);
  EXPECT_EQ(ConstantScreeningMajorant<3>(2.5).ForBall(Vec<3>(0, 0, 0), 1.0).Bound, 2.5);
  EXPECT_EQ(ConstantScreeningMajorant<3>(2.5).ForBall(Vec<3>(0, 0, 0), 1.0).Floor, 0.0);
  EXPECT_EQ(ConstantScreeningMajorant<3>(2.5, 1.5).ForBall(Vec<3>(0, 0, 0), 1.0).Floor, 1.5);
}

TEST(ScreeningMajorant, RefusesBadInput)
{
  const CallableCoefficients<2> field(
    [](const Vec<2>& x, CoefficientSample<2>& out) { out.Alpha = x[0] > 0.5 ? -1.0 : 1.0; });
  EXPECT_THROW(ScreeningBoundGrid<2>(field, Vec<2>(0, 0), Vec<2>(1, 1), {}), std::invalid_argument);
  const ManufacturedField<2> fine(SteepStep());
  EXPECT_THROW(ScreeningBoundGrid<2>(fine, Vec<2>(0, 0), Vec<2>(1, 0), {}), std::invalid_argument);
  EXPECT_THROW(ConstantScreeningMajorant<2>(-1.0), std::invalid_argument);
  EXPECT_THROW(ConstantScreeningMajorant<2>(1.0, 2.0), std::invalid_argument);
  EXPECT_THROW(ConstantScreeningMajorant<2>(1.0, -0.5), std::invalid_argument);
}

// The message names the coefficient and the place.
TEST(ScreeningMajorant, NamesTheUnusableCoefficient)
{
  const CallableCoefficients<3> field(
    [](const Vec<3>& x, CoefficientSample<3>& out) { out.Absorption = x[2] > 0.75 ? -2.0 : 0.0; });
  try
  {
    ScreeningBoundGrid<3>(field, Vec<3>(0, 0, 0), Vec<3>(1, 1, 1), {});
    FAIL() << "no exception";
  }
  catch (const std::invalid_argument& e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("sigma must be finite and >= 0"), std::string::npos) << message;
    EXPECT_NE(message.find("at (0, 0, 0.760417)"), std::string::npos) << message;
  }
}

TEST(ScreeningMajorant, SamplingCountsItsLatticeAndStopsWhenAsked)
{
  const ManufacturedField<2> field(SteepStep());
  ScreeningBoundGrid<2>::Settings settings;
  PreparationMonitor monitor;
  settings.Monitor = &monitor;
  const ScreeningBoundGrid<2> grid(field, Vec<2>(-1, -1), Vec<2>(1, 1), settings);
  // 32 cells of 3 intervals per axis: 97² lattice points.
  EXPECT_EQ(monitor.Total.load(), 97u * 97u);
  EXPECT_EQ(monitor.Done.load(), 97u * 97u);
  // The same bounds as without a monitor.
  const ScreeningBoundGrid<2> plain(field, Vec<2>(-1, -1), Vec<2>(1, 1), {});
  for (double radius : { 0.01, 0.3 })
  {
    const BallScreening a = grid.ForBall(Vec<2>(0.2, -0.1), radius);
    const BallScreening b = plain.ForBall(Vec<2>(0.2, -0.1), radius);
    EXPECT_EQ(a.Bound, b.Bound);
    EXPECT_EQ(a.Floor, b.Floor);
  }
  PreparationMonitor stopped;
  stopped.Stop = true;
  settings.Monitor = &stopped;
  EXPECT_THROW(ScreeningBoundGrid<2>(field, Vec<2>(-1, -1), Vec<2>(1, 1), settings),
    PreparationStopped);
}
