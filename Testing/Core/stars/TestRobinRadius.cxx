// The Robin radius with node bounds (RobinRadius.h) against the same bound
// taken over every primitive: the same radius, bit for bit, on the U (2D),
// the L prism (3D, flat faces) and a sphere (3D, curved: the nodes' normal
// cones open) with Robin coefficients that vary (and are 0 on some
// primitives), at points inside, near the boundary, outside and on the
// Robin part, for star radii from tiny to larger than the shape; and one
// primitive's radius keeps the weights >= 0 and is the largest that does.
// (What the bounds save is measured by ./gridfree bench --stars.)
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
    const double d2 = sampler.SquaredDistance(p, x);
    if (factor * h / mu < radius * radius && d2 < radius * radius)
    {
      radius = std::min(radius, RobinRadiusTree<DIM>::PrimitiveRadius(h / mu, std::sqrt(d2)));
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

  // On the Robin part, where a walk stands after a Robin hit: the
  // primitive x lies on (h and d 0 up to rounding) holds the radius to
  // about 0 (RobinRadius.h).
  const ReflectingBoundarySampler<DIM>& sampler = b.FluxSampler();
  std::uniform_int_distribution<std::int64_t> anyPrimitive(
    0, static_cast<std::int64_t>(b.Reflecting().NumberOfPrimitives()) - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int onRobin = 0;
  for (int i = 0; i < 3000; ++i)
  {
    const std::int64_t p = anyPrimitive(rng);
    if (!(b.RobinCoefficient(p) > 0.0))
    {
      continue;
    }
    Vec<DIM> w;
    const double s = std::sqrt(unit(rng)), t = unit(rng);
    if constexpr (DIM == 2)
    {
      w << 1.0 - t, t;
    }
    else
    {
      w << 1.0 - s, s * (1.0 - t), s * t;
    }
    const Vec<DIM> x = sampler.PointAt(p, w);
    const double R = std::pow(10.0, logR(rng));
    const double fast = b.RobinRadius(x, R);
    EXPECT_EQ(fast, BruteForce<DIM>(b, x, R)) << i;
    EXPECT_LT(fast, 1e-6) << i;
    ++onRobin;
  }
  EXPECT_GT(onRobin, 300);
}

// One primitive at distance d whose plane lies h from x, with t = h/μ: at
// the radius it allows, 1 − μ f(r)/h >= 0 for every r in [d, R] (f as in
// RobinRadius.h), and at a radius 10⁻⁶ larger some r breaks it.
template <int DIM>
void ExpectPrimitiveRadiusTight()
{
  const auto f = [](double r, double R) {
    return DIM == 3 ? r * r * (1.0 - r / R) : r * r * std::log(R / r);
  };
  const auto largest = [&](double d, double R) {
    double most = 0.0;
    for (int k = 0; k <= 4000; ++k)
    {
      const double r = d + (R - d) * k / 4000.0;
      most = std::max(most, f(r, R));
    }
    const double peak = DIM == 3 ? 2.0 * R / 3.0 : R / std::sqrt(M_E);
    return std::max(most, peak > d ? f(peak, R) : 0.0);
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> logU(-4.0, 0.0);
  int nearForm = 0;
  for (int i = 0; i < 400; ++i)
  {
    const double d = std::pow(10.0, logU(rng)), t = std::pow(10.0, 2.0 * logU(rng));
    const double R = RobinRadiusTree<DIM>::PrimitiveRadius(t, d);
    ASSERT_GE(R, d) << i;
    // (f(d) = d²(1 − d/R) loses digits where t << d²)
    EXPECT_LE(largest(d, R), t * (1.0 + 1e-9) + 1e-15 * d * d) << i;
    EXPECT_GT(largest(d, R * (1.0 + 1e-6)), t) << i;
    nearForm += t < d * d / (DIM == 3 ? 3.0 : 2.0) ? 1 : 0;
  }
  EXPECT_GT(nearForm, 50); // both forms are tried
  EXPECT_LT(nearForm, 350);
}

TEST(RobinRadius, OnePrimitiveKeepsTheWeightsAndNoMore)
{
  ExpectPrimitiveRadiusTight<2>();
  ExpectPrimitiveRadiusTight<3>();
}

TEST(RobinRadius, NodeBoundsGiveTheRadiusOfEveryPrimitive)
{
  ExpectSameAsBruteForce<2>(UShape().Mesh, [](const Vec2& c) { return c[1] < 1e-9; });
  ExpectSameAsBruteForce<3>(LPrism().Mesh, LPrismDirichlet);
  ExpectSameAsBruteForce<3>(
    MakeIcosphere(3), [](const Vec3& c) { return c[2] < -0.4; }, -1.2, 1.2);
}
} // namespace robin_radius_tests
