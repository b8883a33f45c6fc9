// Walk on stars outside a closed boundary (MixedBoundary's exterior domain):
// the L prism with Dirichlet bottom and back faces and Neumann elsewhere,
// Laplace with u = 1/|x − a| (a inside the prism: harmonic outside, → 0 at
// infinity), the flux given along the mesh's outward normals as for an
// interior problem. Every point |z| < 5, mean z² in [0.7, 1.4], no back-face
// hits; the same data solved as if the domain were inside (reflection off
// the wrong side, the flux's sign) fails the check.
#include "MixedShapes.h"
#include "StarChecks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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

Calibration Solve(const MixedBoundary<3>& b, const std::vector<Vec3>& points, int walks,
  std::uint64_t& backHits)
{
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  return CalibrateStars<3>(b, settings, points, Potential, walks, 2028, backHits);
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
  std::uint64_t backHits = 0;
  const Calibration c = Solve(outside, points, 256, backHits);
  std::printf("exterior L prism: mean z² %.3f, max |z| %.2f\n", c.MeanZ2, c.MaxAbsZ);
  ExpectCalibrated(c, 150);
  EXPECT_EQ(backHits, 0u);
  const Calibration wrong = Solve(inside, points, 256, backHits);
  std::printf("solved as interior: mean z² %.3f, max |z| %.2f, back-face hits %llu\n",
    wrong.MeanZ2, wrong.MaxAbsZ, static_cast<unsigned long long>(backHits));
  EXPECT_TRUE(wrong.MeanZ2 > 2.0 || wrong.MaxAbsZ > 5.0);
  EXPECT_GT(backHits, 0u);
}

TEST(WalkOnStarsExterior, RefusesWhatItCannotSolve)
{
  const Shape<3> prism = LPrism();
  const MixedBoundary<3> outside = MakeMixed<3>(
    prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0, nullptr, true);
  WalkSettings screened;
  screened.Problem = Equation::ScreenedPoisson;
  screened.ScreeningCoefficient = 1.0;
  EXPECT_THROW(WalkOnStarsEstimator<3>(outside, screened), std::invalid_argument);
  EXPECT_THROW(MakeMixed<3>(prism.Mesh, LPrismDirichlet, Potential, PotentialGradient, true, 1.0,
                 [](const Vec3&) { return 1.0; }, true),
    std::invalid_argument);
}
} // namespace exterior_stars_tests
