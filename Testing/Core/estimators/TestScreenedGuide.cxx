// Tests of gridfree/estimators/ScreenedGuide.h: the von Mises–Fisher
// samplers follow their densities, a guided step is an unbiased estimate of
// the step's C·mean over the sphere whatever the guide's direction, and the
// branch-and-bound search finds the best boundary point. (The calibration
// under strong screening: ErrorBarReliability.GuidedStepsCalibratedUnderStrongScreening.)
#include <gridfree/estimators/ScreenedGuide.h>
#include <gridfree/greens/GreensFunctions.h>
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// E[cos θ] of the von Mises–Fisher density e^{z cos θ}: coth z − 1/z on S²,
// I1(z)/I0(z) on S¹.
double MeanCosine(int dim, double z)
{
  return dim == 3 ? 1.0 / std::tanh(z) - 1.0 / z : BesselI1Scaled(z) / BesselI0Scaled(z);
}

template <int DIM>
void CheckSamplerMeans()
{
  RandomStream rng(21, DIM);
  Vec<DIM> n = Vec<DIM>::Zero();
  n[0] = 0.6;
  n[1] = -0.8;
  for (const double z : { 0.3, 2.0, 40.0 })
  {
    const int count = 20000;
    double sum = 0.0, sum2 = 0.0, sideways = 0.0;
    for (int i = 0; i < count; ++i)
    {
      const Vec<DIM> w = SampleVonMisesFisher<DIM>(n, z, rng);
      ASSERT_NEAR(w.norm(), 1.0, 1e-12);
      const double c = w.dot(n);
      sum += c;
      sum2 += c * c;
      sideways += w[0] * 0.8 + w[1] * 0.6; // the orthogonal direction in the plane
    }
    const double mean = sum / count;
    const double stderror = std::sqrt((sum2 / count - mean * mean) / count);
    EXPECT_NEAR(mean, MeanCosine(DIM, z), 5.0 * stderror + 1e-12) << DIM << "D, z " << z;
    EXPECT_NEAR(sideways / count, 0.0, 5.0 / std::sqrt(double(count))) << DIM << "D, z " << z;
  }
}

TEST(ScreenedGuide, VonMisesFisherSamplersFollowTheirDensities)
{
  CheckSamplerMeans<2>();
  CheckSamplerMeans<3>();
}

// E[factor · φ(ω)] = C · mean over the sphere of φ, for φ a plane wave
// e^{z ω·m} in another direction m (its mean: 1/C): so E = 1, for a guide
// pointing anywhere; and no factor exceeds C/(1 − α).
template <int DIM>
void CheckGuidedStepIsUnbiased()
{
  SimplexMesh<DIM> mesh;
  if constexpr (DIM == 3)
  {
    mesh = MakeIcosphere(1);
  }
  else
  {
    mesh = MakeCircle(12);
  }
  Boundary<DIM> boundary;
  std::vector<double> ones(mesh.Vertices.size(), 1.0);
  boundary.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points, 1, ones);
  const double c = 400.0, radius = 0.1; // z = 2
  const ScreenedGuide<DIM> guide(boundary, c);
  ASSERT_FALSE(guide.Empty());
  const YukawaGreensFunction<DIM> green(radius, c);
  const double z = std::sqrt(c) * radius;
  const Vec<DIM> x = Vec<DIM>::Constant(0.05);
  Vec<DIM> n;
  ASSERT_TRUE(guide.Direction(x, n));
  for (const double angle : { 0.0, 1.0, 2.5 })
  {
    // m at `angle` from the guide's direction, in the plane of n and e0.
    Vec<DIM> t = Vec<DIM>::Zero();
    t[0] = 1.0;
    t = (t - t.dot(n) * n).normalized();
    const Vec<DIM> m = std::cos(angle) * n + std::sin(angle) * t;
    RandomStream rng(22, DIM);
    const int count = 40000;
    double sum = 0.0, sum2 = 0.0, largest = 0.0;
    for (int i = 0; i < count; ++i)
    {
      double factor = 0.0;
      const Vec<DIM> w = guide.Step(x, radius, green, rng, factor);
      largest = std::max(largest, factor);
      const double y = factor * std::exp(z * w.dot(m));
      sum += y;
      sum2 += y * y;
    }
    const double mean = sum / count;
    const double stderror = std::sqrt((sum2 / count - mean * mean) / count);
    EXPECT_NEAR(mean, 1.0, 5.0 * stderror + 1e-12) << DIM << "D, angle " << angle;
    EXPECT_LE(largest, ScreenedGuide<DIM>::LargestFactor(green.BoundaryWeight()) * (1.0 + 1e-12));
  }
}

TEST(ScreenedGuide, GuidedStepIsUnbiasedWhereverItPoints2D)
{
  CheckGuidedStepIsUnbiased<2>();
}

TEST(ScreenedGuide, GuidedStepIsUnbiasedWhereverItPoints3D)
{
  CheckGuidedStepIsUnbiased<3>();
}

// The search's answer against every centroid, with values that vary over
// orders of magnitude (the largest log|g| − √c·distance).
TEST(ScreenedGuide, SearchFindsTheBestBoundaryPoint)
{
  const SimplexMesh<3> mesh = MakeIcosphere(3);
  std::mt19937 gen(23);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> values;
  for (std::size_t i = 0; i < mesh.Vertices.size(); ++i)
  {
    values.push_back(std::exp(8.0 * unit(gen)));
  }
  Boundary<3> boundary;
  boundary.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points, 1, values);
  for (const double c : { 1.0, 100.0, 1e4 })
  {
    const ScreenedGuide<3> guide(boundary, c);
    for (int q = 0; q < 200; ++q)
    {
      const Vec3 x(0.5 * unit(gen), 0.5 * unit(gen), 0.5 * unit(gen));
      double best = -1e300;
      Vec3 bestPoint = Vec3::Zero();
      for (const auto& s : mesh.Simplices)
      {
        const Vec3 centroid = (mesh.Vertices[s[0]] + mesh.Vertices[s[1]] + mesh.Vertices[s[2]]) / 3.0;
        const double g = (values[s[0]] + values[s[1]] + values[s[2]]) / 3.0;
        const double score = std::log(g) - std::sqrt(c) * (centroid - x).norm();
        if (score > best)
        {
          best = score;
          bestPoint = centroid;
        }
      }
      Vec3 n;
      ASSERT_TRUE(guide.Direction(x, n));
      EXPECT_NEAR((n - (bestPoint - x).normalized()).norm(), 0.0, 1e-9) << "c " << c << ", query " << q;
    }
  }
}
// The guide's directions from points inside agree where the data lead one
// way (a plane wave e^{√c e·y}, whose largest contributions come from one
// side from everywhere): there Automatic guides mildly screened walks
// (Problem::LeadingGuide). Where the data come from two sides (radial data
// on an ellipse, largest at both ends) or from all around (constant data:
// each point's nearest boundary point), the directions cancel.
template <int DIM>
double AgreementOf(const SimplexMesh<DIM>& mesh, double c, const std::function<double(const Vec<DIM>&)>& g)
{
  std::vector<double> values;
  for (const Vec<DIM>& v : mesh.Vertices)
  {
    values.push_back(g(v));
  }
  Boundary<DIM> boundary;
  boundary.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points, 1, values);
  const std::vector<Vec<DIM>> inside = InteriorLattice<DIM>(boundary, 8);
  EXPECT_GT(inside.size(), DIM == 2 ? 40u : 200u); // of 64 and 512 cells
  return ScreenedGuide<DIM>(boundary, c).Agreement(inside);
}

TEST(ScreenedGuide, DirectionsAgreeWhereTheDataLeadOneWay)
{
  const SimplexMesh<2> circle = MakeCircle(256);
  SimplexMesh<2> ellipse = circle;
  for (Vec2& v : ellipse.Vertices)
  {
    v[1] *= 0.6;
  }
  const double planeWave2 = AgreementOf<2>(circle, 9.0, [](const Vec2& y) { return std::exp(3.0 * y[0]); });
  const double radial = AgreementOf<2>(ellipse, 9.0, [](const Vec2& y) { return std::cosh(3.0 * y.norm()); });
  const double constant = AgreementOf<2>(circle, 9.0, [](const Vec2&) { return 1.0; });
  const SimplexMesh<3> sphere = MakeIcosphere(3);
  const double planeWave3 = AgreementOf<3>(sphere, 4.0, [](const Vec3& y) { return std::exp(2.0 * y[0]); });
  const double twoSides = AgreementOf<3>(sphere, 4.0, [](const Vec3& y) { return std::cosh(2.0 * y[0]); });
  std::printf("agreement: plane waves %.3f (2D) %.3f (3D); radial %.3f, constant %.3f, two sides %.3f\n",
    planeWave2, planeWave3, radial, constant, twoSides);
  EXPECT_GE(planeWave2, 0.9);
  EXPECT_GE(planeWave3, 0.9);
  EXPECT_LT(radial, 0.5);
  EXPECT_LT(constant, 0.5);
  EXPECT_LT(twoSides, 0.5);
}
} // namespace
