// Two-sided boundary values (diffusion curves and surfaces, paper Sec. 6.4):
// the side test against point-in-polygon and point-in-tetrahedron truth,
// near sharp vertices and edges where a primitive's own normal is wrong,
// and walk on spheres with different values on the two sides of a circle and
// a sphere against the interior and exterior closed forms.
#include "EstimatorChecks.h"

#include <gtest/gtest.h>

#include <random>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// Points scattered within `spread` of random points of the mesh's primitives.
template <int DIM>
std::vector<Vec<DIM>> PointsNearMesh(const SimplexMesh<DIM>& mesh, int count, double spread,
  std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Vec<DIM>> points;
  while (static_cast<int>(points.size()) < count)
  {
    const auto& s = mesh.Simplices[rng() % mesh.Simplices.size()];
    // A point of the simplex, often exactly a vertex or on an edge, where
    // the side test is hardest.
    double w[3] = { u(rng), u(rng), u(rng) };
    const int snap = static_cast<int>(rng() % 3);
    if (snap == 0)
    {
      w[1] = w[2] = 0.0;
    }
    else if (snap == 1)
    {
      w[2] = 0.0;
    }
    double total = 0.0;
    for (int k = 0; k < DIM; ++k)
    {
      total += w[k];
    }
    Vec<DIM> p = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      p += (w[k] / total) * mesh.Vertices[static_cast<std::size_t>(s[k])];
    }
    Vec<DIM> d;
    for (int i = 0; i < DIM; ++i)
    {
      d[i] = n(rng);
    }
    points.push_back(p + spread * u(rng) * d.normalized());
  }
  return points;
}

// A counter-clockwise polygon with a sharp spike (interior angle about 11°)
// and a sharp notch (a reflex vertex with about 11° outside).
SimplexMesh<2> SpikeAndNotch()
{
  SimplexMesh<2> mesh;
  mesh.Vertices = { { 0, 0 }, { 1, 0 }, { 2, 0.1 }, { 1, 0.2 }, { 1, 1 }, { 0.5, 0.05 },
    { 0, 1 } };
  const std::int64_t n = static_cast<std::int64_t>(mesh.Vertices.size());
  for (std::int64_t i = 0; i < n; ++i)
  {
    mesh.Simplices.push_back({ i, (i + 1) % n });
  }
  return mesh;
}

bool InsidePolygon(const SimplexMesh<2>& mesh, const Vec2& x)
{
  bool inside = false;
  for (const auto& s : mesh.Simplices)
  {
    const Vec2& a = mesh.Vertices[static_cast<std::size_t>(s[0])];
    const Vec2& b = mesh.Vertices[static_cast<std::size_t>(s[1])];
    if ((a[1] > x[1]) != (b[1] > x[1]) &&
      x[0] < a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
    {
      inside = !inside;
    }
  }
  return inside;
}

// A regular tetrahedron, faces wound outward: dihedral angles of 70.5°, so
// the normals of two faces meeting at an edge make an obtuse angle.
SimplexMesh<3> Tetrahedron()
{
  SimplexMesh<3> mesh;
  mesh.Vertices = { { 1, 1, 1 }, { 1, -1, -1 }, { -1, 1, -1 }, { -1, -1, 1 } };
  mesh.Simplices = { { 0, 1, 2 }, { 0, 3, 1 }, { 0, 2, 3 }, { 1, 3, 2 } };
  return mesh;
}

bool InsideTetrahedron(const SimplexMesh<3>& mesh, const Vec3& x)
{
  for (const auto& f : mesh.Simplices)
  {
    const Vec3& a = mesh.Vertices[static_cast<std::size_t>(f[0])];
    const Vec3 n = (mesh.Vertices[static_cast<std::size_t>(f[1])] - a)
                     .cross(mesh.Vertices[static_cast<std::size_t>(f[2])] - a);
    if ((x - a).dot(n) > 0.0)
    {
      return false;
    }
  }
  return true;
}

// Counts the points whose Side disagrees with `expected`, and those a test
// with the closest primitive's own normal would get wrong.
template <int DIM, class Expected>
void CountSideErrors(const SimplexMesh<DIM>& mesh, const std::vector<Vec<DIM>>& points,
  Expected expected, int& errors, int& primitiveNormalErrors)
{
  Boundary<DIM> boundary = MakeBoundary<DIM>(
    mesh, { [](const Vec<DIM>&) { return 1.0; }, [](const Vec<DIM>&) { return -1.0; } });
  boundary.SetTwoSided(true);
  errors = primitiveNormalErrors = 0;
  for (const Vec<DIM>& x : points)
  {
    const auto hit = boundary.ClosestPoint(x);
    const int truth = expected(x);
    errors += boundary.Side(x, hit) != truth ? 1 : 0;
    const double d = (x - hit.point).dot(boundary.PrimitiveNormal(hit.primitive));
    primitiveNormalErrors += (d > 0.0 ? 1 : -1) != truth ? 1 : 0;
    // The value follows the side: front 1, back −1.
    double g = 0.0;
    boundary.Evaluate(x, hit, &g);
    EXPECT_NEAR(g, double(truth), 1e-12);
  }
}

WalkSettings ExteriorSettings(int dim)
{
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(double(dim));
  s.Exterior = ExteriorStrategy::ExactReturn;
  return s;
}
} // namespace

// A counter-clockwise polygon's front (its segments' left side) is inside.
TEST(TwoSidedBoundary, SideAtSharpVerticesOfAPolygon)
{
  const SimplexMesh<2> mesh = SpikeAndNotch();
  const auto points = PointsNearMesh<2>(mesh, 20000, 0.03, 11);
  int errors = 0, primitiveNormalErrors = 0;
  CountSideErrors<2>(mesh, points,
    [&](const Vec2& x) { return InsidePolygon(mesh, x) ? 1 : -1; }, errors,
    primitiveNormalErrors);
  EXPECT_EQ(errors, 0);
  // The test has teeth: the primitive's normal alone is wrong near the
  // sharp vertices.
  EXPECT_GT(primitiveNormalErrors, 0);
}

// An outward-wound closed surface's front is outside.
TEST(TwoSidedBoundary, SideAtSharpEdgesAndVerticesOfATetrahedron)
{
  const SimplexMesh<3> mesh = Tetrahedron();
  const auto points = PointsNearMesh<3>(mesh, 20000, 0.1, 12);
  int errors = 0, primitiveNormalErrors = 0;
  CountSideErrors<3>(mesh, points,
    [&](const Vec3& x) { return InsideTetrahedron(mesh, x) ? -1 : 1; }, errors,
    primitiveNormalErrors);
  EXPECT_EQ(errors, 0);
  EXPECT_GT(primitiveNormalErrors, 0);
}

TEST(TwoSidedBoundary, OnTheBoundaryBothSidesAreAveragedAndOddComponentsAreRefused)
{
  Boundary<2> boundary = MakeBoundary<2>(MakeCircle(64),
    { [](const Vec2& x) { return x[0]; }, [](const Vec2&) { return 3.0; } });
  EXPECT_EQ(boundary.Components(), 2);
  boundary.SetTwoSided(true);
  EXPECT_EQ(boundary.Components(), 1);
  const Vec2 onCurve(1.0, 0.0); // a vertex
  double g = 0.0;
  boundary.Evaluate(onCurve, boundary.ClosestPoint(onCurve), &g);
  EXPECT_DOUBLE_EQ(g, 0.5 * (1.0 + 3.0));
  const auto inner = boundary.ClosestPoint(Vec2(0.5, 0.1));
  boundary.Evaluate(inner, &g); // no side given
  EXPECT_NEAR(g, 0.5 * (inner.point[0] + 3.0), 1e-12);
  boundary.Evaluate(Vec2(0.5, 0.1), inner, &g); // inside: the front
  EXPECT_NEAR(g, inner.point[0], 1e-12);

  Boundary<2> odd = MakeBoundary<2>(MakeCircle(64), { [](const Vec2& x) { return x[0]; } });
  EXPECT_THROW(odd.SetTwoSided(true), std::invalid_argument);
}

// Front (inside the counter-clockwise circle) u = x; back (outside) 1 + x:
// the interior solution is x, the bounded exterior one 1 + x/r².
TEST(TwoSidedBoundary, CircleWithDifferentValuesInsideAndOutside)
{
  const Field<2> inside = [](const Vec2& x) { return x[0]; };
  const Field<2> outside = [](const Vec2& x) { return 1.0 + x[0] / x.squaredNorm(); };
  Boundary<2> boundary = MakeBoundary<2>(MakeCircle(4096), { inside, outside });
  boundary.SetTwoSided(true);
  const WalkSettings s = ExteriorSettings(2);
  ExpectCalibrated(CheckEstimator<2>(boundary, s, RandomPointsInBall<2>(300, 0.9, 21), { inside },
                     256, 31)[0],
    300);
  ExpectCalibrated(CheckEstimator<2>(boundary, s, RandomPointsInBall<2>(300, 3.0, 22, 1.1),
                     { outside }, 256, 32)[0],
    300);
  // With one side's values everywhere, the other side's closed form fails.
  Boundary<2> oneSided = MakeBoundary<2>(MakeCircle(4096), { inside });
  const Calibration wrong = CheckEstimator<2>(
    oneSided, s, RandomPointsInBall<2>(300, 3.0, 22, 1.1), { outside }, 256, 32)[0];
  EXPECT_GT(wrong.MaxAbsZ, 5.0);
}

// Front (outside the outward-wound sphere) the Newton potential of a point
// inside, back (inside) u = x y + z: each side's closed form.
TEST(TwoSidedBoundary, SphereWithDifferentValuesInsideAndOutside)
{
  const Vec3 pole(0.2, 0.1, -0.15);
  const Field<3> outside = [pole](const Vec3& x) { return 1.0 / (x - pole).norm(); };
  const Field<3> inside = [](const Vec3& x) { return x[0] * x[1] + x[2]; };
  Boundary<3> boundary = MakeBoundary<3>(MakeIcosphere(4), { outside, inside });
  boundary.SetTwoSided(true);
  const WalkSettings s = ExteriorSettings(3);
  ExpectCalibrated(CheckEstimator<3>(boundary, s, RandomPointsInBall<3>(300, 0.9, 23), { inside },
                     256, 33)[0],
    300);
  ExpectCalibrated(CheckEstimator<3>(boundary, s, RandomPointsInBall<3>(300, 3.0, 24, 1.1),
                     { outside }, 256, 34)[0],
    300);
}
