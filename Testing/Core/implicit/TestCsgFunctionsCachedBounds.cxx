// Tests of the cached bounds that let CSG trees of meshes step at mesh speed
// (CsgFunctions.h, MeshSignedDistance.h, DistanceBoundGrid::Range):
// * a mesh's Range() holds its exact signed value and tells the side at
//   most points away from the surface; its StepBound() is an empty ball
//   within 1 + relaxation of |φ|, exact below ε; Project() is the closest
//   point;
// * a tree's Range(), StepBound() and Project() keep the same promises for
//   unions, intersections, differences, blends, nested trees and trees
//   mixing meshes with analytic shapes, and Project() succeeds at most
//   points near the boundary (the path walks take when they stop);
// * walks on the union of two overlapping mesh spheres, where both operands
//   decide near the seam, match a harmonic function (|z| < 5, mean z² near
//   1), and so do walks through a tree whose cached ranges would pick the
//   wrong operand if a sign were lost.
#include "EstimatorChecks.h"
#include "TestMeshes.h"
#include <gridfree/boundary/Boundary.h>
#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/MeshSignedDistance.h>
#include <gridfree/implicit/SignedDistanceFunctions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
constexpr double kRelaxation = 0.2;
constexpr double kEpsilon = 1e-3;

template <int DIM>
std::shared_ptr<MeshSignedDistance<DIM>> Mesh(const SimplexMesh<DIM>& mesh)
{
  return MeshSignedDistance<DIM>::Create(mesh.Vertices, mesh.Simplices);
}

// The same surface as a soup with every other primitive reversed (the
// sign then comes from rays).
template <int DIM>
SimplexMesh<DIM> Soup(const SimplexMesh<DIM>& mesh)
{
  SimplexMesh<DIM> soup;
  for (std::size_t i = 0; i < mesh.Simplices.size(); ++i)
  {
    std::array<std::int64_t, DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      soup.Vertices.push_back(mesh.Vertices[static_cast<std::size_t>(mesh.Simplices[i][k])]);
      p[k] = static_cast<std::int64_t>(soup.Vertices.size()) - 1;
    }
    if (i % 2 == 1)
    {
      std::swap(p[0], p[1]);
    }
    soup.Simplices.push_back(p);
  }
  return soup;
}

// 1,000 points uniform in a box, and as many within 0.05 of the boundary of φ
// (where walks spend most steps and stop).
template <int DIM>
std::vector<Vec<DIM>> QueryPoints(const SignedDistanceFunction<DIM>& phi, double half,
  std::uint32_t seed)
{
  std::vector<Vec<DIM>> points = RandomPointsInBox<DIM>(1000, half, seed);
  int near = 0;
  for (const Vec<DIM>& x : RandomPointsInBox<DIM>(100000, half, seed + 1))
  {
    if (near < 1000 && std::abs(phi.Value(x)) < 0.05)
    {
      points.push_back(x);
      ++near;
    }
  }
  EXPECT_EQ(near, 1000);
  return points;
}

struct Shares
{
  double SignTold = 0.0; // Range() excludes 0
  double Projected = 0.0; // Project() succeeded, of the points near the boundary
};

// The promises of Range(), StepBound() and Project() at every point.
template <int DIM>
Shares CheckPromises(const SignedDistanceFunction<DIM>& phi, const std::vector<Vec<DIM>>& points,
  const std::string& name)
{
  int told = 0;
  int near = 0;
  int projected = 0;
  for (const Vec<DIM>& x : points)
  {
    const double v = phi.Value(x);
    const double tol = 1e-12 * (1.0 + std::abs(v));
    const ImplicitRange r = phi.Range(x);
    EXPECT_LE(r.Low, v + tol) << name << " at " << x.transpose();
    EXPECT_GE(r.High, v - tol) << name << " at " << x.transpose();
    told += r.Low > 0.0 || r.High < 0.0;

    const double step = phi.StepBound(x, kRelaxation, kEpsilon);
    EXPECT_LE(step, std::abs(v) + tol) << name << " at " << x.transpose();
    EXPECT_GE(step * (1.0 + kRelaxation), std::abs(v) - tol) << name << " at " << x.transpose();
    if (step < kEpsilon)
    {
      EXPECT_NEAR(step, std::abs(v), tol) << name << " at " << x.transpose();
    }

    if (std::abs(v) < 0.05)
    {
      ++near;
      Vec<DIM> p;
      std::int64_t part = -1;
      if (phi.Project(x, p, part))
      {
        ++projected;
        EXPECT_NEAR(phi.Value(p), 0.0, 1e-9) << name << " at " << x.transpose();
        EXPECT_NEAR((x - p).norm(), std::abs(v), 1e-9) << name << " at " << x.transpose();
        EXPECT_GE(part, 0);
        EXPECT_LT(part, phi.NumberOfParts());
        EXPECT_EQ(phi.Sample(p).part, part) << name << " at " << x.transpose();
      }
    }
  }
  Shares s;
  s.SignTold = static_cast<double>(told) / static_cast<double>(points.size());
  s.Projected = near ? static_cast<double>(projected) / near : 0.0;
  return s;
}
} // namespace

TEST(CsgCachedBounds, MeshesHoldTheirPromises)
{
  struct Case
  {
    const char* Name;
    std::shared_ptr<MeshSignedDistance<3>> Phi;
  };
  const Case cases[] = { { "icosphere", Mesh(MakeIcosphere(4)) },
    { "icosphere soup (ray sign)", Mesh(Soup(MakeIcosphere(3))) },
    { "cube", Mesh(MakeCube(6)) } };
  for (const Case& c : cases)
  {
    const Shares s = CheckPromises<3>(*c.Phi, QueryPoints<3>(*c.Phi, 1.5, 3), c.Name);
    // Half the points lie within 0.05 of the surface; most are told even
    // there.
    EXPECT_GT(s.SignTold, 0.7) << c.Name;
    EXPECT_EQ(s.Projected, 1.0) << c.Name;
  }
  const auto circle = Mesh(MakeCircle(200));
  const Shares s = CheckPromises<2>(*circle, QueryPoints<2>(*circle, 1.5, 5), "circle");
  EXPECT_GT(s.SignTold, 0.7);
  EXPECT_EQ(s.Projected, 1.0);
}

TEST(CsgCachedBounds, TreesHoldTheirPromises)
{
  const auto big = Mesh(MakeIcosphere(4));
  const auto inside = Mesh(MakeIcosphere(3, 0.3));
  const auto around = Mesh(MakeIcosphere(3, 1.1));
  const auto left = Mesh(MakeIcosphere(3, 0.8, Vec3(-0.4, 0.0, 0.0)));
  const auto right = Mesh(Soup(MakeIcosphere(3, 0.8, Vec3(0.4, 0.1, 0.0))));
  const auto box = std::make_shared<BoxDistance<3>>(Vec3::Constant(0.6), Vec3::Constant(0.6));
  const auto ball = std::make_shared<SphereDistance<3>>(Vec3(0.0, 0.5, 0.0), 0.9);
  using Csg = CsgDistance<3>;
  struct Case
  {
    const char* Name;
    std::shared_ptr<Csg> Phi;
    double MinimumProjected;
  };
  const auto pair = std::make_shared<Csg>(CsgOperation::Union, left, right);
  const Case cases[] = {
    { "union with a sphere inside", std::make_shared<Csg>(CsgOperation::Union, big, inside), 0.99 },
    { "intersection with a sphere just around",
      std::make_shared<Csg>(CsgOperation::Intersection, big, around), 0.99 },
    // Analytic operands have no projection of their own (Newton steps).
    { "difference with an analytic box",
      std::make_shared<Csg>(CsgOperation::Difference, big, box), 0.75 },
    { "union of overlapping spheres", pair, 0.95 },
    { "intersection of overlapping spheres",
      std::make_shared<Csg>(CsgOperation::Intersection, left, right), 0.95 },
    { "nested: (left ∪ right) ∩ analytic ball",
      std::make_shared<Csg>(CsgOperation::Intersection, pair, ball), 0.35 },
    { "nested: big − ((left ∩ box) ∪ inside)", std::make_shared<Csg>(CsgOperation::Difference, big,
      std::make_shared<Csg>(CsgOperation::Union, std::make_shared<Csg>(CsgOperation::Intersection, left, box), inside)), 0.9 },
    // Blends never project (Newton steps instead), but bound and step.
    { "blended union", std::make_shared<Csg>(CsgOperation::Union, left, right, 0.2), 0.0 },
  };
  for (const Case& c : cases)
  {
    EXPECT_TRUE(c.Phi->CachesBounds());
    const Shares s = CheckPromises<3>(*c.Phi, QueryPoints<3>(*c.Phi, 1.5, 7), c.Name);
    EXPECT_GE(s.Projected, c.MinimumProjected) << c.Name;
    if (c.MinimumProjected == 0.0)
    {
      EXPECT_EQ(s.Projected, 0.0) << c.Name;
    }
  }
  // Trees of analytic shapes keep their exact, uncached path.
  const Csg analytic(CsgOperation::Union, box, ball);
  EXPECT_FALSE(analytic.CachesBounds());
  const Vec3 x(0.1, 0.2, 0.3);
  EXPECT_EQ(analytic.StepBound(x, kRelaxation, kEpsilon), std::abs(analytic.Value(x)));
}

// Walks on the union of two overlapping mesh spheres (a soup and a clean
// mesh), and on a sphere minus the union of a box and a small sphere, with
// boundary data harmonic in R³: the means match it and the variances are
// calibrated. A step or projection from the wrong operand would end walks
// off the boundary (inside the other sphere) and bias them.
TEST(CsgCachedBoundsWalks, CsgOfMeshesMatchHarmonicData)
{
  const auto left = Mesh(MakeIcosphere(3, 0.8, Vec3(-0.4, 0.0, 0.0)));
  const auto right = Mesh(Soup(MakeIcosphere(3, 0.8, Vec3(0.4, 0.1, 0.0))));
  const auto big = Mesh(MakeIcosphere(4));
  const auto box = std::make_shared<BoxDistance<3>>(Vec3::Constant(0.6), Vec3::Constant(0.6));
  const auto small = Mesh(MakeIcosphere(2, 0.25, Vec3(-0.4, -0.3, 0.2)));
  using Csg = CsgDistance<3>;
  const std::shared_ptr<const SignedDistanceFunction<3>> domains[] = {
    std::make_shared<Csg>(CsgOperation::Union, left, right),
    std::make_shared<Csg>(CsgOperation::Difference, big,
      std::make_shared<Csg>(CsgOperation::Union, box, small)) };
  const Field<3> g = [](const Vec3& x) { return std::exp(x[0]) * std::cos(x[1]) + 0.5 * x[2]; };
  const auto values = std::make_shared<CallableBoundaryValues<3>>(
    [g](const Vec3& p, std::int64_t, double* out) { out[0] = g(p); }, 1);
  std::uint32_t seed = 41;
  for (const auto& phi : domains)
  {
    std::vector<Vec3> points;
    for (const Vec3& x : RandomPointsInBox<3>(4000, 1.0, seed++))
    {
      if (phi->Value(x) < -0.02 && points.size() < 200)
      {
        points.push_back(x);
      }
    }
    ASSERT_EQ(points.size(), 200u);
    Boundary<3> boundary;
    boundary.SetGeometry(std::make_shared<ImplicitBoundaryGeometry<3>>(phi), values);
    WalkSettings settings;
    settings.Epsilon = 1e-4 * boundary.Diagonal();
    const Calibration c = CheckEstimator<3>(boundary, settings, points, { g }, 512, seed++)[0];
    EXPECT_EQ(c.EscapedFraction, 0.0);
    EXPECT_EQ(c.TruncatedFraction, 0.0);
    ExpectCalibrated(c, 200);
  }
}
