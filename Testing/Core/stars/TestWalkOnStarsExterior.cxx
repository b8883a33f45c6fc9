// Walk on stars outside a closed boundary (MixedBoundary's exterior domain):
// the L prism with Dirichlet bottom and back faces and Neumann elsewhere,
// Laplace with u = 1/|x − a| (a inside the prism: harmonic outside, → 0 at
// infinity), the flux given along the mesh's outward normals as for an
// interior problem. Every point |z| < 5, mean z² in [0.7, 1.4], no back-face
// hits; the same data solved as if the domain were inside (reflection off
// the wrong side, the flux's sign) fails the check. A Robin part outside,
// and the screened equation outside against e^{−√c r}/r. Through a Problem that
// answers both sides (WalkSettings::MixedBothSides), the points outside get
// the exterior's value and gradient and those inside the same bits as
// without it.
#include <gridfree/problem/Problem.h>

#include "MixedShapes.h"
#include "StarChecks.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

namespace exterior_stars_tests
{
using namespace gridfree;
using namespace gridfree::testing;

const Vec3 kCharge(0.3, 0.3, 0.3);
double Potential(const Vec3& x) { return 1.0 / (x - kCharge).norm(); }
Vec3 PotentialGradient(const Vec3& x)
{
  const Vec3 d = x - kCharge;
  return Vec3(-d / std::pow(d.norm(), 3));
}

// Points around the prism, outside it and at least 0.06 from it.
std::vector<Vec3> PointsOutside(const MixedBoundary<3>& inside, int count, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 1.8);
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < count)
  {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double d = std::min(inside.Dirichlet().Distance(p), inside.Reflecting().Distance(p));
    if (d > 0.06 && !inside.Inside(p))
    {
      points.push_back(p);
    }
  }
  return points;
}

// The Robin coefficient of every primitive of a boundary's reflecting part.
std::vector<double> RobinCoefficients(const MixedBoundary<3>& b)
{
  std::vector<double> mu(b.Reflecting().NumberOfPrimitives());
  for (std::size_t i = 0; i < mu.size(); ++i)
  {
    mu[i] = b.RobinCoefficient(static_cast<std::int64_t>(i));
  }
  return mu;
}

Calibration Solve(const MixedBoundary<3>& b, const std::vector<Vec3>& points, int walks,
  std::uint64_t& backHits)
{
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  return CalibrateStars<3>(b, settings, points, Potential, walks, 2028, backHits);
}

// 256 walks at `points` outside: calibrated, no back-face hits.
void ExpectCalibratedOutside(const char* name, const MixedBoundary<3>& outside, const std::vector<Vec3>& points)
{
  std::uint64_t backHits = 0;
  const Calibration c = Solve(outside, points, 256, backHits);
  std::printf("%s: mean z² %.3f, max |z| %.2f\n", name, c.MeanZ2, c.MaxAbsZ);
  ExpectCalibrated(c, static_cast<int>(points.size()));
  EXPECT_EQ(backHits, 0u);
}

TEST(WalkOnStarsExterior, LPrismWithANeumannPart)
{
  const Shape<3> prism = LPrism();
  const MixedBoundary<3> inside =
    MakeMixed<3>(prism.Mesh, LPrismDirichlet, Potential, PotentialGradient);
  const MixedBoundary<3> outside = MakeMixed<3>(
    prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0, nullptr, true);
  ASSERT_TRUE(outside.IsExterior());
  const auto points = PointsOutside(inside, 150, 3);
  ExpectCalibratedOutside("exterior L prism", outside, points);
  std::uint64_t backHits = 0;
  const Calibration wrong = Solve(inside, points, 256, backHits);
  std::printf("solved as interior: mean z² %.3f, max |z| %.2f, back-face hits %llu\n",
    wrong.MeanZ2, wrong.MaxAbsZ, static_cast<unsigned long long>(backHits));
  EXPECT_TRUE(wrong.MeanZ2 > 2.0 || wrong.MaxAbsZ > 5.0);
  EXPECT_GT(backHits, 0u);
}

// A Robin top face (μ = 1.5) outside: the condition ∂u/∂n + μu = h along
// the normal out of the exterior domain (MixedBoundary::Set), the other
// reflecting faces Neumann with the flux along the mesh's normals. The
// same data with the Robin part's ∂u/∂n taken along the mesh's normals
// instead (h for the interior's convention) must fail the check.
TEST(WalkOnStarsExterior, LPrismWithARobinPart)
{
  const Shape<3> prism = LPrism();
  const RobinRule<3> top = [](const Vec3& c) { return c[2] > 0.59 ? 1.5 : 0.0; };
  const MixedBoundary<3> inside =
    MakeMixed<3>(prism.Mesh, LPrismDirichlet, Potential, PotentialGradient);
  const MixedBoundary<3> outside = MakeMixed<3>(
    prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0, top, true);
  ASSERT_TRUE(outside.IsExterior());
  ASSERT_TRUE(outside.HasRobin());
  const auto points = PointsOutside(inside, 150, 5);
  ExpectCalibratedOutside("exterior L prism, Robin top", outside, points);

  // The interior's data (∂u/∂n along the mesh's normals) on the same
  // exterior domain: the Robin faces' h off by 2 ∂u/∂n.
  const MixedBoundary<3> interiorData =
    MakeMixed<3>(prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0, top);
  MixedBoundary<3> wrongSide;
  wrongSide.Set(interiorData.SharedDirichlet(), interiorData.SharedReflecting(),
    RobinCoefficients(interiorData), true, {}, true);
  std::uint64_t backHits = 0;
  const Calibration wrong = Solve(wrongSide, points, 256, backHits);
  std::printf("Robin data of the interior's convention: mean z² %.3f, max |z| %.2f\n",
    wrong.MeanZ2, wrong.MaxAbsZ);
  EXPECT_TRUE(wrong.MeanZ2 > 2.0 || wrong.MaxAbsZ > 5.0);
}

// The screened equation outside: u = e^{−√c r}/r, r = |x − a| (Yukawa, a
// inside the prism), c = 4, the same split. 1,024 walks: the flux terms
// near a, rare from points far out, make the walks' values heavy-tailed
// (at 256 walks mean z² 1.28–1.37 over four point sets, |z| up to 8, all
// low; at 8,192, 1.04: no bias).

TEST(WalkOnStarsExterior, ScreenedOutsideTheLPrism)
{
  constexpr double sqrtC = 2.0;
  const Field<3> yukawa = [](const Vec3& x) {
    const double r = (x - kCharge).norm();
    return std::exp(-sqrtC * r) / r;
  };
  const Gradient<3> grad = [](const Vec3& x) {
    const Vec3 d = x - kCharge;
    const double r = d.norm();
    return Vec3(-(1.0 / r + sqrtC) * std::exp(-sqrtC * r) / (r * r) * d);
  };
  const Shape<3> prism = LPrism();
  const MixedBoundary<3> inside = MakeMixed<3>(prism.Mesh, LPrismDirichlet, yukawa, grad);
  const MixedBoundary<3> outside =
    MakeMixed<3>(prism.Mesh, LPrismDirichlet, yukawa, grad, true, 1.0, nullptr, true);
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  settings.Problem = Equation::ScreenedPoisson;
  settings.ScreeningCoefficient = sqrtC * sqrtC;
  std::uint64_t backHits = 0;
  const Calibration c =
    CalibrateStars<3>(outside, settings, PointsOutside(inside, 150, 4), yukawa, 1024, 2030, backHits);
  std::printf("screened exterior L prism: mean z² %.3f, max |z| %.2f\n", c.MeanZ2, c.MaxAbsZ);
  ExpectCalibrated(c, 150);
  EXPECT_EQ(backHits, 0u);
}

// Points inside the prism at least 0.06 from its boundary.
std::vector<Vec3> PointsInside(const MixedBoundary<3>& inside, int count, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < count)
  {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double d = std::min(inside.Dirichlet().Distance(p), inside.Reflecting().Distance(p));
    if (d > 0.06 && inside.Inside(p))
    {
      points.push_back(p);
    }
  }
  return points;
}

TEST(WalkOnStarsExterior, ProblemAnswersBothSides)
{
  const Shape<3> prism = LPrism();
  const auto boundary = std::make_shared<const MixedBoundary<3>>(
    MakeMixed<3>(prism.Mesh, LPrismDirichlet, Potential, PotentialGradient));
  const std::vector<Vec3> outside = PointsOutside(*boundary, 100, 5);
  const std::vector<Vec3> inside = PointsInside(*boundary, 30, 6);
  std::vector<std::array<double, 3>> probe;
  for (const auto* list : { &outside, &inside })
  {
    for (const Vec3& p : *list)
    {
      probe.push_back({ p[0], p[1], p[2] });
    }
  }
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  settings.MixedBothSides = true;
  const Problem<3> both(boundary, settings);
  ASSERT_TRUE(both.AnswersOutside());
  BatchRequest request;
  request.WalksPerPoint = 256;
  request.Seed = 2029;
  request.Derivatives.Gradient = true;
  request.Derivatives.ControlVariates = true;
  const BatchEstimates e = both.EstimateAll(probe, request);
  const SampleLayout& layout = e.Summary.Layout;
  ASSERT_GE(layout.Gradient, 0);
  EXPECT_EQ(e.Summary.BackFaceHits, 0u);

  // Outside: the exterior problem's value and gradient.
  Calibration value, gradient;
  for (std::size_t i = 0; i < outside.size(); ++i)
  {
    const double z = (e.Value(i) - Potential(outside[i])) / std::sqrt(e.ValueVariance(i));
    value.MeanZ2 += z * z / static_cast<double>(outside.size());
    value.MaxAbsZ = std::max(value.MaxAbsZ, std::isfinite(z) ? std::abs(z) : 1e300);
    const Vec3 exact = PotentialGradient(outside[i]);
    for (int a = 0; a < 3; ++a)
    {
      const double za = (e.Mean(i, layout.Gradient + a) - exact[a]) /
        std::sqrt(e.Variance(i, layout.Gradient + a));
      gradient.MeanZ2 += za * za / (3.0 * static_cast<double>(outside.size()));
      gradient.MaxAbsZ = std::max(gradient.MaxAbsZ, std::isfinite(za) ? std::abs(za) : 1e300);
    }
  }
  value.Points = static_cast<int>(outside.size());
  gradient.Points = static_cast<int>(3 * outside.size());
  std::printf("both sides, outside: value mean z² %.3f (max |z| %.2f), gradient %.3f (%.2f)\n",
    value.MeanZ2, value.MaxAbsZ, gradient.MeanZ2, gradient.MaxAbsZ);
  ExpectCalibrated(value, value.Points);
  ExpectCalibrated(gradient, gradient.Points);

  // Inside: the interior problem's walks, bit for bit.
  settings.MixedBothSides = false;
  const Problem<3> interior(boundary, settings);
  EXPECT_FALSE(interior.AnswersOutside());
  const std::vector<std::array<double, 3>> insideProbe(probe.begin() + outside.size(), probe.end());
  const BatchEstimates alone = interior.EstimateAll(insideProbe, request);
  for (std::size_t k = 0; k < inside.size(); ++k)
  {
    const std::size_t i = outside.size() + k;
    EXPECT_EQ(e.Value(i), alone.Value(k));
    EXPECT_EQ(e.Mean(i, layout.Gradient), alone.Mean(k, layout.Gradient));
  }

  // With a Robin part too (LPrismWithARobinPart checks its answers).
  settings.MixedBothSides = true;
  const auto robin = std::make_shared<const MixedBoundary<3>>(MakeMixed<3>(prism.Mesh,
    LPrismDirichlet, Potential, PotentialGradient, true, 1.0, [](const Vec3&) { return 1.0; }));
  EXPECT_TRUE(Problem<3>(robin, settings).AnswersOutside());
}

TEST(WalkOnStarsExterior, RefusesWhatItCannotSolve)
{
  const Shape<3> prism = LPrism();
  const MixedBoundary<3> outside = MakeMixed<3>(
    prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0, nullptr, true);
  WalkSettings poisson;
  poisson.Problem = Equation::Poisson;
  EXPECT_THROW(WalkOnStarsEstimator<3>(outside, poisson), std::invalid_argument);
}
} // namespace exterior_stars_tests
