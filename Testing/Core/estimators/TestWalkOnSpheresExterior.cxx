// Exterior problems (paper Sec. 2.6): probe points outside a closed boundary
// solve the Dirichlet problem with u → 0 at infinity (3D) or u bounded (2D).
// Tests the return sampler of ExteriorReturn.h and the estimator against
// closed forms outside a sphere, a cube and a circle, for both strategies.
#include "EstimatorChecks.h"
#include <gridfree/estimators/ExteriorReturn.h>

#include <gtest/gtest.h>

#include <algorithm>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
constexpr int Points = 400;

double KolmogorovSmirnov(std::vector<double> samples, const std::function<double(double)>& cdf)
{
  std::sort(samples.begin(), samples.end());
  double d = 0.0;
  const double n = static_cast<double>(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    const double f = cdf(samples[i]);
    d = std::max({ d, std::abs(f - i / n), std::abs((i + 1) / n - f) });
  }
  return d;
}
} // namespace

// 3D: the cosine t of the return point's angle to x has the CDF
// F(t) = (ρ² − a²)/(2a) [ (ρ² + a² − 2aρt)^(−1/2) − 1/(ρ + a) ], a = ρ²/r.
TEST(ExteriorReturn, HittingDistribution3D)
{
  const Vec3 c(0.5, -0.2, 0.1);
  const double rho = 1.5;
  for (const double r : { 1.6, 3.0, 30.0, 3e4 })
  {
    const Vec3 dir = Vec3(1, 2, -2).normalized();
    const Vec3 x = c + r * dir;
    const double a = rho * rho / r;
    RandomStream rng(PointKey(1, x.data()), 0);
    std::vector<double> t;
    const int n = 20000;
    for (int i = 0; i < n; ++i)
    {
      const Vec3 y = SampleExteriorReturn<3>(x, c, rho, rng);
      ASSERT_NEAR((y - c).norm(), rho, 1e-12);
      t.push_back((y - c).dot(dir) / rho);
    }
    auto cdf = [&](double s) {
      return (rho * rho - a * a) / (2 * a) *
        (1.0 / std::sqrt(rho * rho + a * a - 2 * a * rho * s) - 1.0 / (rho + a));
    };
    EXPECT_LT(KolmogorovSmirnov(t, cdf), 1.95 / std::sqrt(double(n))) << "r = " << r;
    // The uniform distribution on the sphere (no Kelvin image) must fail
    // where the kernel is concentrated.
    if (r < 5.0)
    {
      EXPECT_GT(KolmogorovSmirnov(t, [](double s) { return 0.5 * (s + 1); }),
        1.95 / std::sqrt(double(n)));
    }
  }
  EXPECT_DOUBLE_EQ(ReturnProbability<3>(4.0, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(ReturnProbability<2>(4.0, 1.0), 1.0);
}

// 2D: the angle follows the wrapped Cauchy law with concentration ρ/r.
TEST(ExteriorReturn, HittingDistribution2D)
{
  const Vec2 c(0.5, -0.2);
  const double rho = 2.0;
  for (const double r : { 2.2, 5.0, 1e3 })
  {
    const Vec2 x = c + r * Vec2(0.6, 0.8);
    const double k = rho / r;
    RandomStream rng(7, 0);
    std::vector<double> theta;
    const int n = 20000;
    for (int i = 0; i < n; ++i)
    {
      const Vec2 y = SampleExteriorReturn<2>(x, c, rho, rng);
      ASSERT_NEAR((y - c).norm(), rho, 1e-12);
      const Vec2 d = (y - c) / rho;
      theta.push_back(std::atan2(0.6 * d[1] - 0.8 * d[0], 0.6 * d[0] + 0.8 * d[1]));
    }
    auto cdf = [k](double t) {
      // CDF of the wrapped Cauchy law on (−π, π).
      return 0.5 + std::atan((1 + k) / (1 - k) * std::tan(0.5 * t)) / M_PI;
    };
    EXPECT_LT(KolmogorovSmirnov(theta, cdf), 1.95 / std::sqrt(double(n))) << "r = " << r;
  }
}

namespace
{
template <int DIM>
WalkSettings Exterior(ExteriorStrategy strategy, Equation equation = Equation::Laplace)
{
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  s.Exterior = strategy;
  s.Problem = equation;
  return s;
}

const Vec3 Pole3(0.2, 0.1, -0.15);
const Field<3> Newton3 = [](const Vec3& x) { return 1.0 / (x - Pole3).norm(); };

template <int DIM>
std::vector<Vec<DIM>> Shell(int count, double inner, double outer, std::uint32_t seed)
{
  return RandomPointsInBall<DIM>(count, outer, seed, inner);
}
} // namespace

TEST(ExteriorWalkOnSpheres3D, NewtonPotentialOutsideSphere)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { Newton3 });
  const auto points = Shell<3>(Points, 1.15, 3.0, 80);
  const Calibration c = CheckEstimator<3>(
    boundary, Exterior<3>(ExteriorStrategy::ExactReturn), points, { Newton3 }, 512, 700)[0];
  ExpectCalibrated(c, Points);
  EXPECT_GT(c.EscapedFraction, 0.2); // walks do leave, and are counted
  EXPECT_EQ(c.TruncatedFraction, 0.0);
}

// The textbook alternative, roulette with survival probability ρ_far/r at
// every far step and reweighting, is also unbiased but its weights are
// heavy-tailed: returning with the exact probability has a lower variance.
// Prints the measured figures.
TEST(ExteriorWalkOnSpheres3D, ExactReturnHasLowerVarianceThanRoulette)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { Newton3 });
  const auto points = Shell<3>(50, 1.15, 3.0, 86);
  auto meanSampleVariance = [&](ExteriorStrategy strategy, double& steps) {
    WalkOnSpheresEstimator<3> estimator(boundary, Exterior<3>(strategy));
    RunningStatistics stats(1);
    double sum = 0.0;
    steps = 0.0;
    for (const Vec3& p : points)
    {
      stats.Reset();
      WalkCounters counters;
      estimator.EstimatePoint(p.data(), 707, 0, 512, stats, counters);
      sum += stats.SampleVariance(0);
      steps += counters.MeanSteps() / points.size();
    }
    return sum / points.size();
  };
  double exactSteps = 0.0, rouletteSteps = 0.0;
  const double exact = meanSampleVariance(ExteriorStrategy::ExactReturn, exactSteps);
  const double roulette = meanSampleVariance(ExteriorStrategy::RussianRoulette, rouletteSteps);
  std::printf("exterior: per-walk variance exact return %.4g (%.1f steps/walk), roulette %.4g "
              "(%.1f steps/walk), ratio %.2f\n",
    exact, exactSteps, roulette, rouletteSteps, roulette / exact);
  EXPECT_LT(exact, roulette);
}

TEST(ExteriorWalkOnSpheres3D, NewtonPotentialOutsideCube)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeCube(40), { Newton3 });
  std::vector<Vec3> points;
  for (const Vec3& p : Shell<3>(4 * Points, 1.0, 3.5, 81))
  {
    if (p.cwiseAbs().maxCoeff() > 1.2 && points.size() < std::size_t(Points))
    {
      points.push_back(p);
    }
  }
  ExpectCalibrated(CheckEstimator<3>(boundary, Exterior<3>(ExteriorStrategy::ExactReturn),
                     points, { Newton3 }, 512, 701)[0],
    Points);
}

// Counting escapes as 0 at a far sphere of radius ρ (the annulus solution)
// instead of returning walks is biased, and the check sees it.
TEST(ExteriorWalkOnSpheres3D, CheckRejectsTheAnnulusSolution)
{
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { Newton3 });
  const auto points = Shell<3>(Points, 1.15, 3.0, 82);
  const double rho = 4.0;
  const Field<3> annulus = [rho](const Vec3& x) {
    // Harmonic, equal to 1/|x − p| on the sphere and 0 on |x| = ρ only
    // approximately; the exact exterior solution differs by O(1/ρ).
    return Newton3(x) - (1.0 / rho);
  };
  EXPECT_GT(CheckEstimator<3>(boundary, Exterior<3>(ExteriorStrategy::ExactReturn), points,
              { annulus }, 512, 702)[0]
              .MaxAbsZ,
    5.0);
}

// Poisson outside a sphere: a Gaussian source in the exterior region, with
// its free-space potential (which vanishes at infinity) as the exact solution.
TEST(ExteriorWalkOnSpheres3D, PoissonWithExteriorSource)
{
  const Vec3 center(2.0, 0.3, 0.0);
  // A broad source: in the large balls of exterior walks a narrow one is a
  // rare event for any sampling strategy, and 512 walks underestimate its
  // spread.
  const double sigma = 0.8, amplitude = 10.0;
  const double mass = amplitude * std::pow(M_PI, 1.5) * sigma * sigma * sigma;
  const Field<3> u = [&](const Vec3& x) {
    const double r = (x - center).norm();
    return -mass * std::erf(r / sigma) / (4.0 * M_PI * r);
  };
  FunctionSource<3> f(
    [&](const Vec3& x) { return amplitude * std::exp(-(x - center).squaredNorm() / (sigma * sigma)); },
    center - Vec3::Constant(8 * sigma), center + Vec3::Constant(8 * sigma));
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { u });
  const auto points = Shell<3>(Points, 1.15, 3.0, 83);
  WalkSettings s = Exterior<3>(ExteriorStrategy::ExactReturn, Equation::Poisson);
  s.Sampling = SourceSampling::MultipleImportance;
  ExpectCalibrated(CheckEstimator<3>(boundary, s, points, { u }, 512, 703, &f)[0], Points);
}

// 2D: the bounded exterior solution u = 1 + x/|x|² outside the unit circle.
TEST(ExteriorWalkOnSpheres2D, BoundedSolutionOutsideCircle)
{
  const Field<2> u = [](const Vec2& x) { return 1.0 + x[0] / x.squaredNorm(); };
  const Boundary<2> boundary = MakeBoundary<2>(MakeCircle(4096), { u });
  const auto points = Shell<2>(Points, 1.15, 3.0, 84);
  const Calibration c = CheckEstimator<2>(
    boundary, Exterior<2>(ExteriorStrategy::ExactReturn), points, { u }, 512, 704)[0];
  ExpectCalibrated(c, Points);
  EXPECT_EQ(c.EscapedFraction, 0.0); // planar Brownian motion always returns
}

// Screened Poisson outside a sphere: u = e^{−s r}/r decays at infinity.
TEST(ExteriorWalkOnSpheres3D, ScreenedPoissonOutsideSphere)
{
  const double c = 1.0;
  const Field<3> u = [c](const Vec3& x) {
    const double r = x.norm();
    return std::exp(-std::sqrt(c) * r) / r;
  };
  const Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { u });
  WalkSettings s = Exterior<3>(ExteriorStrategy::ExactReturn, Equation::ScreenedPoisson);
  s.ScreeningCoefficient = c;
  const auto points = Shell<3>(Points, 1.15, 3.0, 85);
  const Calibration r = CheckEstimator<3>(boundary, s, points, { u }, 512, 705)[0];
  ExpectCalibrated(r, Points);
  EXPECT_EQ(r.TruncatedFraction, 0.0);
}
