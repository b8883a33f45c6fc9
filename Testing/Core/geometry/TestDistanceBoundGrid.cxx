// The grid of cached distance bounds that walk steps use far from a mesh
// (Geometry/DistanceBoundGrid.h, Boundary::StepRadius): every radius it gives
// is an empty ball (never above the brute-force distance), accepted ones are
// at least 1/(1 + accept) of the distance, it serves the deep interior of a
// closed surface, its values do not depend on the thread count, and walks
// that use it still match closed-form harmonic functions.
#include <gridfree/boundary/Boundary.h>
#include "EstimatorChecks.h"
#include <gridfree/geometry/DistanceBoundGrid.h>
#include "RandomSoups.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
template <int DIM>
Boundary<DIM> MakeMeshBoundary(
  const std::vector<Vec<DIM>>& vertices, const std::vector<typename Bvh<DIM>::Primitive>& prims)
{
  Boundary<DIM> boundary;
  boundary.Set(vertices, prims, ValueAssociation::Points, 1,
    std::vector<double>(vertices.size(), 0.0));
  return boundary;
}

// Random points in the boundary box grown by half its size on every side
// (some beyond the grid), checked against brute force. Returns how many the
// grid answered.
template <int DIM>
int CheckBounds(const std::vector<Vec<DIM>>& vertices,
  const std::vector<typename Bvh<DIM>::Primitive>& prims, double accept, int count,
  std::uint64_t seed)
{
  const Boundary<DIM> boundary = MakeMeshBoundary<DIM>(vertices, prims);
  const DistanceBoundGrid<DIM>& grid = boundary.StepBoundGrid();
  EXPECT_FALSE(grid.Empty());
  const Vec<DIM> lo = boundary.BoundsMin();
  const Vec<DIM> extent = boundary.BoundsMax() - lo;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  int answered = 0;
  for (int i = 0; i < count; ++i)
  {
    Vec<DIM> x;
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = lo[k] + u(rng) * extent[k];
    }
    const double r = grid.StepBound(x, accept);
    if (r == 0.0)
    {
      continue;
    }
    ++answered;
    const double d = std::sqrt(BruteForceSquaredDistance<DIM>(Soup<DIM>{ vertices, prims }, x));
    EXPECT_LE(r, d) << "an accepted radius is not an empty ball at " << x.transpose();
    EXPECT_GE(r, d / (1.0 + accept) * (1.0 - 1e-9))
      << "an accepted radius is too small at " << x.transpose();
  }
  return answered;
}

TEST(DistanceBoundGrid, RadiiAreEmptyBallsOnSoups)
{
  for (const double accept : { 0.2, 1.0, 3.0 })
  {
    const Soup<3> soup3 = MakeSoup<3>(4000, 81);
    EXPECT_GT(CheckBounds<3>(soup3.Vertices, soup3.Primitives, accept, 3000, 82), 100);
    const Soup<2> soup2 = MakeSoup<2>(4000, 83);
    EXPECT_GT(CheckBounds<2>(soup2.Vertices, soup2.Primitives, accept, 3000, 84), 100);
  }
}

TEST(DistanceBoundGrid, ServesTheInteriorOfClosedSurfaces)
{
  const auto sphere = MakeIcosphere(5);
  const auto circle = MakeCircle(4000);
  EXPECT_GT(CheckBounds<3>(sphere.Vertices, sphere.Simplices, 0.2, 2000, 85), 100);
  EXPECT_GT(CheckBounds<2>(circle.Vertices, circle.Simplices, 0.2, 2000, 86), 100);

  // Deep inside the sphere (within half its radius) nearly every step that
  // accepts half the distance can skip the hierarchy.
  const Boundary<3> boundary = MakeMeshBoundary<3>(sphere.Vertices, sphere.Simplices);
  std::mt19937_64 rng(87);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  int inside = 0, answered = 0;
  for (int i = 0; i < 2000; ++i)
  {
    const Vec3 x(u(rng), u(rng), u(rng));
    if (x.norm() > 0.5)
    {
      continue;
    }
    ++inside;
    const double r = boundary.StepBoundGrid().StepBound(x, 1.0);
    answered += r > 0.0 ? 1 : 0;
    EXPECT_LE(r, 1.0 - x.norm() + 1e-3); // the icosphere lies within the unit sphere
  }
  EXPECT_GT(answered, 0.95 * inside);
}

// A flat mesh (zero extent along z) and a single segment still get a usable
// grid; a point on the mesh or beyond the grid gets no radius.
TEST(DistanceBoundGrid, FlatAndTinyMeshes)
{
  const std::vector<Vec3> quad = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } };
  const std::vector<Bvh<3>::Primitive> tris = { { 0, 1, 2 }, { 0, 2, 3 } };
  CheckBounds<3>(quad, tris, 1.0, 2000, 88); // points in its plane: bounds hold
  const Boundary<3> flat = MakeMeshBoundary<3>(quad, tris);
  EXPECT_EQ(flat.StepBoundGrid().StepBound(Vec3(0.5, 0.5, 0.0), 1.0), 0.0);
  EXPECT_EQ(flat.StepBoundGrid().StepBound(Vec3(50.0, 0.5, 0.0), 1.0), 0.0);
  EXPECT_EQ(flat.StepBoundGrid().StepBound(
              Vec3(std::numeric_limits<double>::quiet_NaN(), 0.5, 0.5), 1.0),
    0.0);

  const std::vector<Vec2> ends = { { 0, 0 }, { 1, 0 } };
  const std::vector<Bvh<2>::Primitive> segment = { { 0, 1 } };
  const Boundary<2> one = MakeMeshBoundary<2>(ends, segment);
  EXPECT_FALSE(one.StepBoundGrid().Empty());
  EXPECT_LE(one.StepBoundGrid().StepBound(Vec2(0.5, 0.3), 3.0), 0.3);

  DistanceBoundGrid<3> none;
  none.Build<int>(BoundingBox<3>(), 1000, 0.1, [](const Vec3&, int&) { return 1.0; });
  EXPECT_TRUE(none.Empty());
  EXPECT_EQ(none.StepBound(Vec3::Zero(), 1.0), 0.0);
}

// The grid is filled in parallel; its bounds, and so which steps use it,
// are the same on one thread and on two.
TEST(DistanceBoundGrid, SameBoundsForOneAndTwoThreads)
{
  const auto sphere = MakeIcosphere(4);
  auto radii = [&](int threads)
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const Boundary<3> boundary = MakeMeshBoundary<3>(sphere.Vertices, sphere.Simplices);
    std::vector<double> r;
    std::mt19937_64 rng(89);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    for (int i = 0; i < 3000; ++i)
    {
      r.push_back(boundary.StepBoundGrid().StepBound(Vec3(u(rng), u(rng), u(rng)), 1.0));
    }
    return r;
  };
  const auto one = radii(1);
  const auto two = radii(2);
  ASSERT_EQ(one, two);
}

// Walks on a sphere with the grid (the default) and without it both match a
// harmonic function, and the grid changes the walks (it is used). Steps may
// be half the distance here, so that the grid serves many of them on this
// small mesh.
TEST(DistanceBoundGrid, WalksWithTheGridMatchHarmonicFunctions)
{
  const SimplexMesh<3> sphere = MakeIcosphere(5);
  const Field<3> harmonic = [](const Vec3& p) { return p[0] * p[0] - p[1] * p[1] + p[2]; };
  Boundary<3> withGrid = MakeBoundary<3>(sphere, { harmonic });
  Boundary<3> without = MakeBoundary<3>(sphere, { harmonic });
  without.SetBoundGrid(false);
  withGrid.SetStepRelaxation(1.0);
  without.SetStepRelaxation(1.0);
  WalkSettings settings;
  settings.Epsilon = 1e-4 * withGrid.Diagonal();
  const auto points = RandomPointsInBall<3>(40, 0.6, 90);
  const Calibration a = CheckEstimator<3>(withGrid, settings, points, { harmonic }, 400, 91)[0];
  const Calibration b = CheckEstimator<3>(without, settings, points, { harmonic }, 400, 91)[0];
  for (const Calibration* c : { &a, &b })
  {
    EXPECT_LT(c->MaxAbsZ, 5.0);
    EXPECT_GT(c->MeanZ2, 0.6);
    EXPECT_LT(c->MeanZ2, 1.6);
  }
  EXPECT_NE(a.MeanSteps, b.MeanSteps);
}
} // namespace
