// The Robin radius with node bounds (RobinRadius.h) against the same bound
// taken over every primitive: the same radius, bit for bit, on the U (2D),
// the L prism (3D, flat faces) and a sphere (3D, curved: the nodes' normal
// cones open) with Robin coefficients that vary (and are 0 on some
// primitives), at points inside, near the boundary and outside, for star
// radii from tiny to larger than the shape. (What the bounds save is
// measured by ./gridfree bench --stars.)
#include <gridfree/stars/MixedBoundary.h>

#include "MixedShapes.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace robin_radius_tests
{
using namespace gridfree;
using namespace gridfree::testing;

template <int DIM>
double Mu(const Vec<DIM>& c)
{
  const double s = std::sin(7.0 * c[0] + 3.0 * c[1]);
  return s > -0.3 ? 0.2 + 4.0 * std::abs(s) : 0.0;
}

// The radius from every Robin primitive, as RobinRadius.h defines it.
template <int DIM>
double BruteForce(const MixedBoundary<DIM>& b, const Vec<DIM>& x, double R)
{
  const ReflectingBoundarySampler<DIM>& sampler = b.FluxSampler();
  const double factor = DIM == 3 ? 27.0 / 4.0 : 2.0 * M_E;
  double radius = R;
  for (std::int64_t p = 0; p < static_cast<std::int64_t>(b.Reflecting().NumberOfPrimitives()); ++p)
  {
    const double mu = b.RobinCoefficient(p);
    if (!(mu > 0.0))
    {
      continue;
    }
    const double h = std::abs((x - sampler.FirstVertex(p)).dot(b.OutwardNormal(p)));
    const double bound2 = factor * h / mu;
    const double d2 = sampler.SquaredDistance(p, x);
    if (bound2 < radius * radius && d2 < radius * radius)
    {
      radius = std::min(radius, std::sqrt(std::max(d2, bound2)));
    }
  }
  return radius;
}

template <int DIM>
void ExpectSameAsBruteForce(const SimplexMesh<DIM>& mesh,
  const std::function<bool(const Vec<DIM>&)>& isDirichlet, double low = -0.3, double high = 1.6)
{
  const MixedBoundary<DIM> b = MakeMixed<DIM>(mesh, isDirichlet,
    [](const Vec<DIM>&) { return 0.0; }, [](const Vec<DIM>&) { return Vec<DIM>(Vec<DIM>::Zero()); },
    true, 1.0, Mu<DIM>);
  ASSERT_TRUE(b.HasRobin());
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(low, high);
  std::uniform_real_distribution<double> logR(-6.0, 0.5);
  int shrunk = 0;
  for (int i = 0; i < 3000; ++i)
  {
    Vec<DIM> x;
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = u(rng);
    }
    const double R = std::pow(10.0, logR(rng));
    const double fast = b.RobinRadius(x, R);
    EXPECT_EQ(fast, BruteForce<DIM>(b, x, R)) << i;
    shrunk += fast < R ? 1 : 0;
  }
  EXPECT_GT(shrunk, 300); // the radius is shrunk often enough to matter
}

TEST(RobinRadius, NodeBoundsGiveTheRadiusOfEveryPrimitive)
{
  ExpectSameAsBruteForce<2>(UShape().Mesh, [](const Vec2& c) { return c[1] < 1e-9; });
  ExpectSameAsBruteForce<3>(LPrism().Mesh, LPrismDirichlet);
  ExpectSameAsBruteForce<3>(
    MakeIcosphere(3), [](const Vec3& c) { return c[2] < -0.4; }, -1.2, 1.2);
}
} // namespace robin_radius_tests
