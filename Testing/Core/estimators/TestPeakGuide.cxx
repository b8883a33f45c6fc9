// Tests of gridfree/estimators/PeakGuide.h: the peak and how far it stands
// out are found from the primitives' centroids, and a step toward it is an
// unbiased estimate of the mean over the step's sphere (a wrong density
// or weight would move it), with a far smaller variance than a uniform step
// where u is the potential of a charge near the peak, and factors below
// 1/(1 − α). (The calibration: ErrorBarReliability.StepsTowardTheDataPeak.)
#include <gridfree/estimators/PeakGuide.h>
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
std::shared_ptr<Boundary<3>> SphereWithData(const Field<3>& g)
{
  const SimplexMesh<3> mesh = MakeIcosphere(3);
  auto values = std::make_shared<CallableBoundaryValues<3>>(
    [g](const Vec3& p, std::int64_t, double* out) { out[0] = g(p); }, 1);
  auto boundary = std::make_shared<Boundary<3>>();
  boundary->SetMesh(mesh.Vertices, mesh.Simplices, values);
  return boundary;
}

// The Yukawa potential e^{−k r}/r of a charge at q (1/r for k = 0).
Field<3> Charge(const Vec3& q, double k)
{
  return [q, k](const Vec3& y) { return std::exp(-k * (y - q).norm()) / (y - q).norm(); };
}

struct StepMoments
{
  double Mean = 0.0;
  double StandardError = 0.0;
  double Variance = 0.0;
  double LargestFactor = 0.0;
};

// N steps of radius R from x, toward the guide's peak or uniform.
StepMoments Steps(const PeakGuide<3>* guide, const Vec3& x, double radius, const Field<3>& f,
  int n, std::uint64_t key)
{
  RandomStream rng(key, 0);
  double sum = 0.0, sum2 = 0.0;
  StepMoments m;
  for (int i = 0; i < n; ++i)
  {
    double factor = 1.0;
    const Vec3 omega = guide ? guide->Step(x, radius, rng, factor) : SampleUnitSphere<3>(rng);
    EXPECT_NEAR(omega.norm(), 1.0, 1e-12);
    const double v = factor * f(x + radius * omega);
    sum += v;
    sum2 += v * v;
    m.LargestFactor = std::max(m.LargestFactor, factor);
  }
  m.Mean = sum / n;
  m.Variance = sum2 / n - m.Mean * m.Mean;
  m.StandardError = std::sqrt(m.Variance / n);
  return m;
}
} // namespace

TEST(PeakGuide, FindsThePeakAndHowFarItStandsOut)
{
  const Vec3 pole(1.05, 0.0, 0.0);
  const PeakGuide<3> peaked(*SphereWithData(Charge(pole, 0.0)), 0.0);
  ASSERT_TRUE(peaked.Found());
  // The centroid nearest the pole, on the sphere of 642 vertices.
  EXPECT_GT(peaked.PeakPoint()[0], 0.95);
  EXPECT_GT(peaked.StandsOut(), PeakGuide<3>::kStandsOut);
  const PeakGuide<3> flat(*SphereWithData([](const Vec3&) { return -2.0; }), 0.0);
  ASSERT_TRUE(flat.Found());
  EXPECT_NEAR(flat.StandsOut(), 1.0, 1e-12);
  const PeakGuide<3> smooth(*SphereWithData([](const Vec3& y) { return std::exp(y[0]); }), 1.0);
  EXPECT_LT(smooth.StandsOut(), 3.0);
  EXPECT_FALSE(PeakGuide<3>(*SphereWithData([](const Vec3&) { return 0.0; }), 0.0).Found());
}

TEST(PeakGuide, StepsAreUnbiasedMeansOverTheSphere)
{
  const Vec3 pole(1.05, 0.0, 0.0);
  for (const double c : { 0.0, 6.25, 400.0 })
  {
    const double k = std::sqrt(c);
    const PeakGuide<3> guide(*SphereWithData(Charge(pole, k)), c);
    // Mean over a sphere of radius R of a solution of Δu = c·u: u at its
    // centre times sinh(kR)/(kR) (1 for c = 0).
    const auto sphereMean = [k](double value, double radius) {
      return k > 0.0 ? value * std::sinh(k * radius) / (k * radius) : value;
    };
    const Vec3 e = Vec3(0.3, -0.5, 0.8).normalized();
    const Field<3> wave = [k, e](const Vec3& y) { return k > 0.0 ? std::exp(k * e.dot(y)) : y[2]; };
    for (const Vec3& x : { Vec3(0.2, 0.3, -0.1), Vec3(0.7, 0.05, 0.0) })
    {
      const double radius = 0.9 * (guide.PeakPoint() - x).norm() * 0.5;
      const int n = 40000;
      // The charge itself (the guide's own density) and a plane wave (no
      // relation to it): both means are exact.
      const StepMoments charge = Steps(&guide, x, radius, Charge(pole, k), n, 7);
      EXPECT_NEAR(charge.Mean, sphereMean(Charge(pole, k)(x), radius), 5.0 * charge.StandardError)
        << "c " << c << ", x " << x.transpose();
      const StepMoments plane = Steps(&guide, x, radius, wave, n, 8);
      EXPECT_NEAR(plane.Mean, sphereMean(wave(x), radius), 5.0 * plane.StandardError + 1e-14)
        << "c " << c << ", x " << x.transpose();
      EXPECT_LE(std::max(charge.LargestFactor, plane.LargestFactor),
        PeakGuide<3>::LargestFactor() * (1.0 + 1e-12));
      // Toward the charge, the steps' variance is a fraction of uniform
      // steps'.
      const StepMoments uniform = Steps(nullptr, x, radius, Charge(pole, k), n, 9);
      EXPECT_LT(charge.Variance, 0.5 * uniform.Variance) << "c " << c << ", x " << x.transpose();
    }
  }
}
