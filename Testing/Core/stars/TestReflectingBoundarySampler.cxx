// The samplers walk on stars draws from, against their densities: points on
// the Neumann part in a ball (ReflectingBoundarySampler.h) and the ray
// weights of the screened equation (StarKernels.h).
#include <gridfree/greens/GreensFunctions.h>
#include <gridfree/sampling/BallSampling.h>
#include <gridfree/stars/ReflectingBoundarySampler.h>
#include <gridfree/stars/StarKernels.h>

#include "BlockShapes.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace
{
using namespace gridfree;
using namespace gridfree::testing;

// Each sample reports the density Pdf() gives for its primitive; the
// counts per primitive pass a chi-square test against pdf × area; and
// E[1(z in ball)/pdf] is the area of the surface inside the ball, which a
// uniform sampling of the whole surface estimates independently.
template <int DIM>
void ExpectSamplesFollowTheDensity(const SimplexMesh<DIM>& mesh, const Vec<DIM>& x, double R)
{
  ReflectingBoundarySampler<DIM> sampler;
  const std::vector<std::array<std::int64_t, DIM>> prims(mesh.Simplices.begin(), mesh.Simplices.end());
  sampler.Build(mesh.Vertices, prims);
  const int n = 200000;
  std::map<std::int64_t, int> counts;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i)
  {
    RandomStream rng(99, static_cast<std::uint64_t>(i));
    BoundarySample<DIM> s;
    double v = 0.0;
    if (sampler.Sample(x, R, rng, s))
    {
      ASSERT_NEAR(s.Pdf, sampler.Pdf(x, R, s.Primitive), 1e-12 * s.Pdf);
      ASSERT_NEAR((s.Point - sampler.PointAt(s.Primitive, s.Barycentric)).norm(), 0.0, 1e-12);
      counts[s.Primitive] += 1;
      v = (s.Point - x).norm() < R ? 1.0 / s.Pdf : 0.0;
    }
    sum += v;
    sum2 += v * v;
  }
  // Chi-square over primitives expected at least 20 times.
  double chi2 = 0.0;
  int bins = 0;
  for (std::size_t p = 0; p < prims.size(); ++p)
  {
    const double expected =
      n * sampler.Pdf(x, R, static_cast<std::int64_t>(p)) * sampler.Area(static_cast<std::int64_t>(p));
    if (expected >= 20.0)
    {
      const double d = counts[static_cast<std::int64_t>(p)] - expected;
      chi2 += d * d / expected;
      ++bins;
    }
  }
  ASSERT_GT(bins, 20);
  // chi2 ~ bins ± sqrt(2 bins) (one fewer degree of freedom, ignored).
  EXPECT_LT(std::abs(chi2 - bins), 5.0 * std::sqrt(2.0 * bins)) << "bins " << bins;

  // The area inside the ball, both ways.
  const double mean = sum / n;
  const double stderrBall = std::sqrt((sum2 / n - mean * mean) / n);
  double total = 0.0;
  for (std::size_t p = 0; p < prims.size(); ++p)
  {
    total += sampler.Area(static_cast<std::int64_t>(p));
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> cumulative;
  double acc = 0.0;
  for (std::size_t p = 0; p < prims.size(); ++p)
  {
    acc += sampler.Area(static_cast<std::int64_t>(p));
    cumulative.push_back(acc);
  }
  const int m = 400000;
  int inside = 0;
  for (int i = 0; i < m; ++i)
  {
    const std::size_t p = static_cast<std::size_t>(
      std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) - cumulative.begin());
    Vec<DIM> w;
    if constexpr (DIM == 2)
    {
      const double t = u(rng);
      w << 1 - t, t;
    }
    else
    {
      const double s = std::sqrt(u(rng)), t = u(rng);
      w << 1 - s, s * (1 - t), s * t;
    }
    inside += (sampler.PointAt(static_cast<std::int64_t>(std::min(p, prims.size() - 1)), w) - x).norm() < R;
  }
  const double q = double(inside) / m;
  const double areaUniform = total * q;
  const double stderrUniform = total * std::sqrt(q * (1 - q) / m);
  EXPECT_LT(std::abs(mean - areaUniform), 5.0 * std::hypot(stderrBall, stderrUniform))
    << mean << " vs " << areaUniform;
  EXPECT_GT(areaUniform, 0.0);
}

TEST(ReflectingBoundarySampler, FollowsItsDensity2D)
{
  const SimplexMesh<2> comb = MakeBlockShape<2>({ { 0, 0 }, { 1, 0 }, { 2, 0 }, { 0, 1 }, { 2, 1 } }, 16);
  ExpectSamplesFollowTheDensity<2>(comb, Vec2(1.5, 1.2), 0.9);
  ExpectSamplesFollowTheDensity<2>(MakeCircle(500), Vec2(0.3, -0.2), 1.0);
}

TEST(ReflectingBoundarySampler, FollowsItsDensity3D)
{
  const SimplexMesh<3> l3 = MakeBlockShape<3>({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, 6);
  ExpectSamplesFollowTheDensity<3>(l3, Vec3(1.0, 0.8, 0.6), 0.7);
  ExpectSamplesFollowTheDensity<3>(MakeIcosphere(3), Vec3(0.5, 0.1, 0.2), 0.8);
}

TEST(ReflectingBoundarySampler, NothingWhenTheBallMissesTheSurface)
{
  ReflectingBoundarySampler<3> sampler;
  const SimplexMesh<3> sphere = MakeIcosphere(2);
  sampler.Build(sphere.Vertices,
    std::vector<std::array<std::int64_t, 3>>(sphere.Simplices.begin(), sphere.Simplices.end()));
  RandomStream rng(1, 2);
  BoundarySample<3> s;
  EXPECT_FALSE(sampler.Sample(Vec3::Zero(), 0.5, rng, s));
  EXPECT_EQ(sampler.Pdf(Vec3::Zero(), 0.5, 0), 0.0);
  EXPECT_NEAR(sampler.TotalArea(), 4.0 * M_PI, 0.3); // the polyhedron is a little smaller
}

// Q(r) = −|S| r^{n−1} G'(r) for the Yukawa Green's function of the ball,
// Q(0) = 1 and Q(R) = C, over z = sR from 1e-3 to 300.
template <int DIM>
void ExpectRayWeightsMatchTheKernel()
{
  for (double R : { 0.3, 1.0 })
  {
    for (double z : { 1e-3, 0.5, 2.0, 10.0, 60.0, 300.0 })
    {
      const double s = z / R;
      const YukawaGreensFunction<DIM> green(R, s * s);
      EXPECT_NEAR(ScreenedRayWeight<DIM>(1e-9 * R, R, s), 1.0, 1e-6);
      EXPECT_NEAR(ScreenedRayWeight<DIM>(R, R, s), green.BoundaryWeight(),
        1e-10 + 1e-8 * green.BoundaryWeight());
      for (double f : { 0.05, 0.3, 0.6, 0.9 })
      {
        const double r = f * R;
        const double h = 1e-5 * R;
        const double derivative = (green.Value(r + h) - green.Value(r - h)) / (2 * h);
        const double expected = -UnitSphereArea<DIM>() * std::pow(r, DIM - 1) * derivative;
        const double q = ScreenedRayWeight<DIM>(r, R, s);
        EXPECT_NEAR(q, expected, 1e-6 * std::max(1.0, std::abs(expected)) + 1e-12)
          << "R " << R << " z " << z << " r/R " << f;
        EXPECT_GE(q, 0.0);
        EXPECT_LE(q, 1.0);
      }
    }
  }
}

TEST(StarKernels, ScreenedRayWeights2D) { ExpectRayWeightsMatchTheKernel<2>(); }
TEST(StarKernels, ScreenedRayWeights3D) { ExpectRayWeightsMatchTheKernel<3>(); }
} // namespace

// Flat patches: a cube's face is one patch, the L block's top is one L of
// three cells, each triangle of a sphere or of a soup (no shared vertices)
// is its own; the share of plane draws follows the patch's size.
TEST(ReflectingBoundarySampler, FlatPatchesSizeThePlaneDraws)
{
  auto build = [](const SimplexMesh<3>& mesh) {
    ReflectingBoundarySampler<3> sampler;
    sampler.Build(mesh.Vertices,
      std::vector<std::array<std::int64_t, 3>>(mesh.Simplices.begin(), mesh.Simplices.end()));
    return sampler;
  };
  auto patchAreas = [](const SimplexMesh<3>& mesh, const ReflectingBoundarySampler<3>& sampler) {
    std::vector<double> areas;
    for (std::size_t i = 0; i < mesh.Simplices.size(); ++i)
    {
      areas.push_back(sampler.Area(static_cast<std::int64_t>(i)));
    }
    return FlatPatchAreas(mesh.Vertices, mesh.Simplices, areas);
  };

  const SimplexMesh<3> cube = MakeCube(4, 0.5);
  const ReflectingBoundarySampler<3> cubeSampler = build(cube);
  for (double area : patchAreas(cube, cubeSampler))
  {
    EXPECT_NEAR(area, 1.0, 1e-12);
  }
  const double faceReach = std::sqrt(1.0 / M_PI);
  EXPECT_DOUBLE_EQ(cubeSampler.PlaneShare(0, 3.9 * faceReach), 0.5);
  EXPECT_NEAR(cubeSampler.PlaneShare(0, 16.0 * faceReach), 0.125, 1e-12);

  const SimplexMesh<3> l3 = MakeBlockShape<3>({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, 3);
  const std::vector<double> lAreas = patchAreas(l3, build(l3));
  int top = 0;
  for (std::size_t i = 0; i < l3.Simplices.size(); ++i)
  {
    Vec3 c = Vec3::Zero();
    for (std::int64_t v : l3.Simplices[i])
    {
      c += l3.Vertices[static_cast<std::size_t>(v)] / 3.0;
    }
    if (std::abs(c.z() - 1.0) < 1e-12 || std::abs(c.z()) < 1e-12)
    {
      ++top;
      EXPECT_NEAR(lAreas[i], 3.0, 1e-12) << "the L's top and bottom are one patch each";
    }
    else if (std::abs(c.x()) < 1e-12 || std::abs(c.y()) < 1e-12)
    {
      EXPECT_NEAR(lAreas[i], 2.0, 1e-12) << "the two long walls";
    }
  }
  EXPECT_EQ(top, 2 * 3 * 9 * 2);

  const SimplexMesh<3> sphere = MakeIcosphere(3);
  const ReflectingBoundarySampler<3> sphereSampler = build(sphere);
  const std::vector<double> sphereAreas = patchAreas(sphere, sphereSampler);
  SimplexMesh<3> soup;
  for (std::size_t i = 0; i < sphere.Simplices.size(); ++i)
  {
    EXPECT_DOUBLE_EQ(sphereAreas[i], sphereSampler.Area(static_cast<std::int64_t>(i)));
    std::array<std::int64_t, 3> t;
    for (int k = 0; k < 3; ++k)
    {
      t[k] = static_cast<std::int64_t>(soup.Vertices.size());
      soup.Vertices.push_back(sphere.Vertices[static_cast<std::size_t>(sphere.Simplices[i][k])]);
    }
    soup.Simplices.push_back(t);
  }
  const SimplexMesh<3> cubeSoupSource = MakeCube(2, 0.5);
  for (const auto& s : cubeSoupSource.Simplices)
  {
    std::array<std::int64_t, 3> t;
    for (int k = 0; k < 3; ++k)
    {
      t[k] = static_cast<std::int64_t>(soup.Vertices.size());
      soup.Vertices.push_back(cubeSoupSource.Vertices[static_cast<std::size_t>(s[k])] * 3.0);
    }
    soup.Simplices.push_back(t);
  }
  const ReflectingBoundarySampler<3> soupSampler = build(soup);
  const std::vector<double> soupAreas = patchAreas(soup, soupSampler);
  for (std::size_t i = 0; i < soup.Simplices.size(); ++i)
  {
    EXPECT_DOUBLE_EQ(soupAreas[i], soupSampler.Area(static_cast<std::int64_t>(i)));
  }
  // A sphere's triangle is small against a star of radius 0.5: fewer plane draws.
  const double reach = std::sqrt(sphereSampler.Area(0) / M_PI);
  EXPECT_NEAR(sphereSampler.PlaneShare(0, 0.5), 2.0 * reach / 0.5, 1e-15);
  EXPECT_LT(sphereSampler.PlaneShare(0, 0.5), 0.25);
}
