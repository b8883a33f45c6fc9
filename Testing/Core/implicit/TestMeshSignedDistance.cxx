// Tests of a closed mesh as a signed distance function (paper "Monte Carlo
// Geometry Processing", Sec. 5.1.4: CSG of meshes and implicit functions).
//
// The magnitude must be the exact BVH distance and the sign must match an
// analytic inside test of the solid the mesh describes, also on imperfect
// meshes: polygon soups with every vertex duplicated, triangles of mixed
// orientation, repeated triangles and small cracks, and at query points
// aligned with vertices and edges (where a single axis-aligned ray would pass
// through edges or graze them). The analytic tests skip a thin band around
// the surface where mesh and analytic solid may legitimately differ.
// Rays aimed exactly at shared vertices and edges must count one crossing.
// Then the mesh takes part in a CSG difference with an analytic box, and in
// walk-on-spheres solves of the Laplace equation through the implicit
// boundary path (the mesh alone, and the CSG domain with data that is
// harmonic only in that domain, so that a wrong sign biases the result),
// checked for accuracy (|z| < 5) and calibration (mean z² near 1). Seeds are
// fixed, so failures are reproducible.
#include <gridfree/boundary/Boundary.h>
#include <gridfree/boundary/BoundaryValues.h>
#include "EstimatorChecks.h"
#include <gridfree/geometry/Bvh.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/MeshSignedDistance.h>
#include <gridfree/implicit/SignedDistanceFunctions.h>
#include "TestMeshes.h"
#include <gridfree/math/Vector.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
template <int DIM>
using Primitive = typename Bvh<DIM>::Primitive;

// The same surface as a polygon soup: every primitive gets its own copies of
// its vertices, every other one has its orientation reversed, and optionally
// each primitive appears twice (a common defect of exported soups).
template <int DIM>
SimplexMesh<DIM> MakeSoupOf(const SimplexMesh<DIM>& mesh, bool repeatPrimitives)
{
  SimplexMesh<DIM> soup;
  for (std::size_t i = 0; i < mesh.Simplices.size(); ++i)
  {
    std::array<std::int64_t, DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      soup.Vertices.push_back(mesh.Vertices[mesh.Simplices[i][k]]);
      p[k] = static_cast<std::int64_t>(soup.Vertices.size()) - 1;
    }
    if (i % 2 == 1)
    {
      std::swap(p[0], p[1]);
    }
    soup.Simplices.push_back(p);
    if (repeatPrimitives)
    {
      soup.Simplices.push_back(p);
    }
  }
  return soup;
}

// Each triangle shrunk towards its centroid by `fraction`: a soup whose
// triangles no longer meet, with cracks of relative width `fraction` along
// every edge (as left by careless welding or decimation).
SimplexMesh<3> MakeCracked(const SimplexMesh<3>& mesh, double fraction)
{
  SimplexMesh<3> cracked;
  for (const auto& t : mesh.Simplices)
  {
    const Vec3 c = (mesh.Vertices[t[0]] + mesh.Vertices[t[1]] + mesh.Vertices[t[2]]) / 3.0;
    std::array<std::int64_t, 3> p;
    for (int k = 0; k < 3; ++k)
    {
      cracked.Vertices.push_back(c + (1.0 - fraction) * (mesh.Vertices[t[k]] - c));
      p[k] = static_cast<std::int64_t>(cracked.Vertices.size()) - 1;
    }
    cracked.Simplices.push_back(p);
  }
  return cracked;
}

template <int DIM>
std::shared_ptr<MeshSignedDistance<DIM>> MakeFunction(const SimplexMesh<DIM>& mesh)
{
  return MeshSignedDistance<DIM>::Create(mesh.Vertices, mesh.Simplices);
}

// Analytic solids: +1 inside, −1 outside, 0 within `band` of the surface.
int SphereSide(const Vec3& x, double band)
{
  const double r = x.norm();
  return r < 1.0 - band ? 1 : (r > 1.0 + band ? -1 : 0);
}

template <int DIM>
int CubeSide(const Vec<DIM>& x, double band)
{
  const double m = x.cwiseAbs().maxCoeff();
  return m < 1.0 - band ? 1 : (m > 1.0 + band ? -1 : 0);
}

// Compares the sign of φ with `side` (skipping the band, side 0) and |φ|
// with an independently built Bvh over the same mesh; returns the number of
// points compared.
template <int DIM, class Side>
int CheckSigns(const MeshSignedDistance<DIM>& phi, const SimplexMesh<DIM>& mesh,
  const std::vector<Vec<DIM>>& points, Side side)
{
  Bvh<DIM> reference;
  reference.Build(mesh.Vertices, mesh.Simplices);
  int compared = 0;
  int wrong = 0;
  for (const Vec<DIM>& x : points)
  {
    const int s = side(x);
    if (s == 0)
    {
      continue;
    }
    ++compared;
    const double value = phi.Value(x);
    const bool inside = phi.Inside(x);
    EXPECT_EQ(std::abs(value), reference.Distance(x)) << "at " << x.transpose();
    EXPECT_EQ(inside, value < 0.0) << "at " << x.transpose();
    if (inside != (s > 0))
    {
      ++wrong;
      if (wrong <= 10)
      {
        ADD_FAILURE() << "wrong side at " << x.transpose() << ": value " << value;
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  return compared;
}

template <int DIM>
std::vector<Vec<DIM>> UniformPoints(int count, double half, std::uint32_t seed)
{
  return RandomPointsInBox<DIM>(count, half, seed);
}

// Points of the lattice step · Z^DIM in [−half, half]^DIM.
template <int DIM>
std::vector<Vec<DIM>> LatticePoints(double step, double half)
{
  const int n = static_cast<int>(std::lround(half / step));
  std::vector<Vec<DIM>> points;
  std::array<int, DIM> i;
  i.fill(-n);
  while (true)
  {
    Vec<DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = step * i[k];
    }
    points.push_back(p);
    int k = 0;
    while (k < DIM && ++i[k] > n)
    {
      i[k] = -n;
      ++k;
    }
    if (k == DIM)
    {
      break;
    }
  }
  return points;
}

// Points aligned with the cube's vertices, edges and faces: the lattice of
// the mesh vertices (and of the edge midpoints) inside and around the cube,
// and the same points pushed 1e-7 across each face plane, so that rays along
// the axes from them run through mesh vertices and edges or along the
// cube's edges.
std::vector<Vec3> CubeAlignedPoints(int subdivisions)
{
  std::vector<Vec3> points = LatticePoints<3>(1.0 / subdivisions, 1.5);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (std::abs(points[i][k]) == 1.0)
      {
        for (double shift : { -1e-7, 1e-7 })
        {
          Vec3 p = points[i];
          p[k] += shift;
          points.push_back(p);
        }
      }
    }
  }
  // The diagonals through the cube's corners, inside and outside.
  for (int i = -30; i <= 30; ++i)
  {
    const double s = 1.5 * i / 30.0;
    points.emplace_back(s, s, s);
    points.emplace_back(s, -s, s);
    points.emplace_back(s, 1.0, 1.0 + 1e-7);
    points.emplace_back(1.0 - 1e-7, s, 1.0 - 1e-7);
  }
  return points;
}

//------------------------------------------------------------------------------
// 2D: a five-pointed star, star-shaped around the origin. Vertex k lies at
// angle kπ/5 with radius outer (even k) or inner (odd k), the first tip on
// the x axis.
constexpr double StarOuter = 1.0;
constexpr double StarInner = 0.45;

SimplexMesh<2> MakeStar()
{
  SimplexMesh<2> mesh;
  for (int k = 0; k < 10; ++k)
  {
    const double a = M_PI * k / 5.0;
    const double r = k % 2 == 0 ? StarOuter : StarInner;
    mesh.Vertices.emplace_back(r * std::cos(a), r * std::sin(a));
    mesh.Simplices.push_back({ k, (k + 1) % 10 });
  }
  return mesh;
}

// Analytic point-in-star test in polar form: the ray from the origin at the
// angle of x meets the boundary in exactly one point, on the edge of the
// angular sector of x; x is inside iff it is nearer than that point.
// 0 within `band` of the boundary (measured along the ray and to every edge).
int StarSide(const Vec2& x, double band)
{
  const SimplexMesh<2> star = MakeStar();
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& s : star.Simplices)
  {
    const Vec2 a = star.Vertices[s[0]];
    const Vec2 b = star.Vertices[s[1]];
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    nearest = std::min(nearest, (x - (a + t * (b - a))).norm());
  }
  if (nearest <= band)
  {
    return 0;
  }
  double angle = std::atan2(x[1], x[0]);
  if (angle < 0.0)
  {
    angle += 2.0 * M_PI;
  }
  const int k = std::min(9, static_cast<int>(angle / (M_PI / 5.0)));
  const Vec2 a = star.Vertices[k];
  const Vec2 b = star.Vertices[(k + 1) % 10];
  const Vec2 u(std::cos(angle), std::sin(angle));
  // Intersection of the ray s·u with the line a + t (b − a): s = cross(a, e) / cross(u, e).
  const Vec2 e = b - a;
  const double s = (a[0] * e[1] - a[1] * e[0]) / (u[0] * e[1] - u[1] * e[0]);
  return x.norm() < s ? 1 : -1;
}

// Star-aligned query points: on the horizontal and vertical lines through
// every vertex (rays along the axes run through vertices and along no
// edge), and on the rays from the origin through the vertices.
std::vector<Vec2> StarAlignedPoints()
{
  const SimplexMesh<2> star = MakeStar();
  std::vector<Vec2> points;
  for (const Vec2& v : star.Vertices)
  {
    for (int i = -24; i <= 24; ++i)
    {
      const double s = 1.2 * i / 24.0;
      points.emplace_back(s, v[1]);
      points.emplace_back(v[0], s);
      points.push_back((1.2 * std::abs(s)) * v);
    }
  }
  return points;
}

// A closed-form harmonic function of R³ (as in the Laplace tests).
double ExpTrig(const Vec3& x)
{
  return std::exp(std::sqrt(2.0) * x[0]) * std::cos(x[1]) * std::sin(x[2]);
}
} // namespace

//------------------------------------------------------------------------------
TEST(MeshSignedDistance, IcosphereSignAndDistance)
{
  const SimplexMesh<3> sphere = MakeIcosphere(4); // 5120 triangles, sagitta < 1e-3
  const auto phi = MakeFunction<3>(sphere);
  const auto points = UniformPoints<3>(6000, 1.3, 11);
  const int compared =
    CheckSigns<3>(*phi, sphere, points, [](const Vec3& x) { return SphereSide(x, 0.01); });
  EXPECT_GT(compared, 5000);
  // Both sides are well represented.
  int inside = 0;
  for (const Vec3& x : points)
  {
    inside += phi->Inside(x);
  }
  EXPECT_GT(inside, 1000);
  EXPECT_LT(inside, 5000);
}

TEST(MeshSignedDistance, CubeSignAndDistance)
{
  const SimplexMesh<3> cube = MakeCube(8);
  const auto phi = MakeFunction<3>(cube);
  EXPECT_GT(CheckSigns<3>(*phi, cube, UniformPoints<3>(6000, 1.3, 12),
              [](const Vec3& x) { return CubeSide<3>(x, 1e-12); }),
    5900);
  EXPECT_GT(CheckSigns<3>(*phi, cube, CubeAlignedPoints(8),
              [](const Vec3& x) { return CubeSide<3>(x, 0.0); }),
    10000);
}

// Duplicated vertices, mixed orientation, repeated triangles, and queries
// aligned with the mesh's vertices and edges.
TEST(MeshSignedDistance, CubeSoupIsRobust)
{
  const SimplexMesh<3> cube = MakeCube(4);
  for (bool repeat : { false, true })
  {
    const SimplexMesh<3> soup = MakeSoupOf<3>(cube, repeat);
    ASSERT_EQ(soup.Vertices.size(), 3 * cube.Simplices.size());
    const auto phi = MakeFunction<3>(soup);
    EXPECT_GT(CheckSigns<3>(*phi, soup, UniformPoints<3>(4000, 1.3, 13),
                [](const Vec3& x) { return CubeSide<3>(x, 1e-12); }),
      3900);
    EXPECT_GT(CheckSigns<3>(*phi, soup, CubeAlignedPoints(4),
                [](const Vec3& x) { return CubeSide<3>(x, 0.0); }),
      1000);
  }
}

// Cracks of relative width 1e-4 along every edge: a ray through a crack
// misses a crossing, and the vote outweighs it.
TEST(MeshSignedDistance, CrackedCubeIsRobust)
{
  const SimplexMesh<3> cracked = MakeCracked(MakeCube(4), 1e-4);
  const auto phi = MakeFunction<3>(cracked);
  EXPECT_GT(CheckSigns<3>(*phi, cracked, UniformPoints<3>(4000, 1.3, 14),
              [](const Vec3& x) { return CubeSide<3>(x, 1e-3); }),
    3500);
  EXPECT_GT(CheckSigns<3>(*phi, cracked, CubeAlignedPoints(4),
              [](const Vec3& x) { return CubeSide<3>(x, 1e-3); }),
    1000);
}

TEST(MeshSignedDistance, IcosphereSoupIsRobust)
{
  const SimplexMesh<3> soup = MakeSoupOf<3>(MakeIcosphere(3), false);
  const auto phi = MakeFunction<3>(soup);
  EXPECT_GT(CheckSigns<3>(*phi, soup, UniformPoints<3>(3000, 1.3, 15),
              [](const Vec3& x) { return SphereSide(x, 0.01); }),
    2500);
}

TEST(MeshSignedDistance, StarPolygon2D)
{
  const SimplexMesh<2> star = MakeStar();
  for (bool soup : { false, true })
  {
    const SimplexMesh<2> mesh = soup ? MakeSoupOf<2>(star, false) : star;
    const auto phi = MakeFunction<2>(mesh);
    EXPECT_GT(CheckSigns<2>(*phi, mesh, UniformPoints<2>(6000, 1.2, 16),
                [](const Vec2& x) { return StarSide(x, 1e-9); }),
      5900);
    EXPECT_GT(CheckSigns<2>(*phi, mesh, StarAlignedPoints(),
                [](const Vec2& x) { return StarSide(x, 1e-9); }),
      1400);
  }
}

TEST(MeshSignedDistance, Square2D)
{
  const SimplexMesh<2> square = MakeSquare(8);
  const auto phi = MakeFunction<2>(square);
  EXPECT_GT(CheckSigns<2>(*phi, square, LatticePoints<2>(1.0 / 16.0, 1.5),
              [](const Vec2& x) { return CubeSide<2>(x, 0.0); }),
    2000);
}

// Rays aimed exactly at mesh vertices and edge midpoints: the watertight ray
// test reports the crossing in every primitive around the vertex or edge
// (at t equal up to rounding), and they must count as one crossing. From
// inside a convex (or star-shaped) solid every ray crosses exactly once.
TEST(MeshSignedDistance, HitsAtSharedEdgesAndVerticesCountOnce)
{
  const SimplexMesh<3> cube = MakeCube(4);
  for (bool repeat : { false, true })
  {
    const SimplexMesh<3> soup = MakeSoupOf<3>(cube, repeat);
    const auto phi = MakeFunction<3>(soup);
    std::vector<Vec3> targets = cube.Vertices;
    for (const auto& t : cube.Simplices)
    {
      targets.push_back(0.5 * (cube.Vertices[t[0]] + cube.Vertices[t[1]]));
    }
    for (const Vec3& origin : RandomPointsInBox<3>(20, 0.9, 19))
    {
      for (const Vec3& target : targets)
      {
        EXPECT_EQ(phi->Crossings(origin, target - origin), 1)
          << "from " << origin.transpose() << " through " << target.transpose();
      }
    }
  }
  const SimplexMesh<2> star = MakeStar();
  const auto phi2 = MakeFunction<2>(MakeSoupOf<2>(star, false));
  for (const Vec2& origin : RandomPointsInBall<2>(50, 0.3, 20))
  {
    for (const Vec2& target : star.Vertices)
    {
      EXPECT_EQ(phi2->Crossings(origin, target - origin), 1)
        << "from " << origin.transpose() << " through " << target.transpose();
    }
  }
}

// The gradient is the exact unit direction away from the closest point,
// turned inwards inside; on the mesh it is the outward normal whatever the
// triangle's own orientation.
TEST(MeshSignedDistance, GradientIsExact)
{
  const SimplexMesh<3> soup = MakeSoupOf<3>(MakeCube(4), false);
  const auto phi = MakeFunction<3>(soup);
  Bvh<3> reference;
  reference.Build(soup.Vertices, soup.Simplices);
  for (const Vec3& x : UniformPoints<3>(500, 1.3, 17))
  {
    const ClosestPointResult<3> c = reference.ClosestPoint(x);
    Vec3 expected = (x - c.point).normalized();
    if (CubeSide<3>(x, 0.0) > 0)
    {
      expected = -expected;
    }
    EXPECT_LT((phi->Gradient(x) - expected).norm(), 1e-12) << "at " << x.transpose();
  }
  for (const auto& t : soup.Simplices)
  {
    const Vec3 c = (soup.Vertices[t[0]] + soup.Vertices[t[1]] + soup.Vertices[t[2]]) / 3.0;
    int axis = 0;
    c.cwiseAbs().maxCoeff(&axis);
    Vec3 outward = Vec3::Zero();
    outward[axis] = c[axis] > 0.0 ? 1.0 : -1.0;
    ASSERT_LT(std::abs(phi->Value(c)), 1e-15); // the centroid, up to rounding
    EXPECT_LT((phi->Gradient(c) - outward).norm(), 1e-12) << "at " << c.transpose();
    // Just off the face, on either side, the exact gradient is the same.
    EXPECT_LT((phi->Gradient(c + 1e-6 * outward) - outward).norm(), 1e-9);
    EXPECT_LT((phi->Gradient(c - 1e-6 * outward) - outward).norm(), 1e-9);
  }
  // Projection along the gradient lands on the mesh (the closest point).
  const ImplicitBoundaryGeometry<3> geometry(phi);
  for (const Vec3& x : UniformPoints<3>(200, 1.3, 18))
  {
    const ClosestPointResult<3> hit = geometry.ClosestPoint(x);
    EXPECT_LT(reference.Distance(hit.point), 1e-12);
    EXPECT_NEAR(hit.distance, reference.Distance(x), 1e-12);
  }
}

TEST(MeshSignedDistance, InterfaceAndValidation)
{
  const SimplexMesh<3> cube = MakeCube(2, 0.5);
  const auto phi = MakeFunction<3>(cube);
  EXPECT_EQ(phi->NumberOfParts(), 1);
  EXPECT_EQ(phi->Lipschitz(), 1.0);
  EXPECT_EQ(phi->Sample(Vec3(0.1, 0.2, 0.3)).part, 0);
  EXPECT_NEAR(phi->Sample(Vec3(0.1, 0.2, 0.3)).value, -0.2, 1e-15);
  EXPECT_TRUE(phi->Bounds().Min.isApprox(Vec3::Constant(-0.5)));
  EXPECT_TRUE(phi->Bounds().Max.isApprox(Vec3::Constant(0.5)));
  // Far outside the box: positive, the exact distance, and no sign rays.
  EXPECT_DOUBLE_EQ(phi->Value(Vec3(3.5, 0.0, 0.0)), 3.0);
  EXPECT_FALSE(phi->Inside(Vec3(3.5, 0.0, 0.0)));
  // An exact distance is 1-Lipschitz on both sides.
  const BoundingBox<3> box(Vec3::Constant(-0.8), Vec3::Constant(0.8));
  EXPECT_LE(ObservedLipschitz<3>(*phi, box, 4000, 0), 1.0 + 1e-6);

  // Sharing a hierarchy.
  auto tree = std::make_shared<Bvh<3>>();
  tree->Build(cube.Vertices, cube.Simplices);
  const MeshSignedDistance<3> shared(tree, cube.Vertices, cube.Simplices);
  EXPECT_EQ(shared.Hierarchy().get(), tree.get());
  EXPECT_EQ(shared.Value(Vec3(0.1, 0.2, 0.3)), phi->Value(Vec3(0.1, 0.2, 0.3)));

  using Prims = std::vector<Primitive<3>>;
  EXPECT_THROW(MeshSignedDistance<3>::Create({}, {}), std::invalid_argument);
  EXPECT_THROW(MeshSignedDistance<3>::Create(cube.Vertices, {}), std::invalid_argument);
  EXPECT_THROW(MeshSignedDistance<3>::Create({}, cube.Simplices), std::invalid_argument);
  EXPECT_THROW(MeshSignedDistance<3>::Create(cube.Vertices, Prims{ { 0, 1, 99999 } }),
    std::invalid_argument);
  EXPECT_THROW(MeshSignedDistance<3>::Create(cube.Vertices, Prims{ { 0, -1, 2 } }),
    std::invalid_argument);
  std::vector<Vec3> bad = cube.Vertices;
  bad[0][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MeshSignedDistance<3>::Create(bad, cube.Simplices), std::invalid_argument);
  EXPECT_THROW(
    MeshSignedDistance<3>(nullptr, cube.Vertices, cube.Simplices), std::invalid_argument);
  EXPECT_THROW(
    MeshSignedDistance<3>(tree, cube.Vertices, Prims{ { 0, 1, 2 } }), std::invalid_argument);
  EXPECT_THROW(MeshSignedDistance<2>::Create({}, {}), std::invalid_argument);
}

//------------------------------------------------------------------------------
// CSG: the mesh sphere minus an analytic box (the octant corner [0, 1.2]³).
// The sign follows the analytic CSG of the round sphere away from both
// surfaces, and |φ| never exceeds the distance to the mesh CSG's own zero
// set, measured against a dense sampling of that zero set: mesh points
// outside the box and box points inside the mesh. A sampled distance is an
// upper bound of the true one, so |φ| ≤ sampled must hold everywhere.
TEST(MeshSignedDistance, CsgDifferenceWithBox)
{
  const SimplexMesh<3> sphere = MakeIcosphere(4);
  const auto mesh = MakeFunction<3>(sphere);
  const Vec3 boxCenter = Vec3::Constant(0.6);
  const Vec3 boxHalf = Vec3::Constant(0.6);
  const auto box = std::make_shared<BoxDistance<3>>(boxCenter, boxHalf);
  const CsgDistance<3> csg(CsgOperation::Difference, mesh, box);
  const SphereDistance<3> round(Vec3::Zero(), 1.0);

  // Sign against the analytic CSG, away from both surfaces.
  int compared = 0;
  for (const Vec3& x : UniformPoints<3>(4000, 1.3, 21))
  {
    const double a = round.Value(x);
    const double b = box->Value(x);
    if (std::abs(a) < 0.01 || std::abs(b) < 0.01)
    {
      continue;
    }
    ++compared;
    const double analytic = std::max(a, -b);
    EXPECT_EQ(csg.Value(x) < 0.0, analytic < 0.0) << "at " << x.transpose();
  }
  EXPECT_GT(compared, 3000);

  // Dense samples of the zero set.
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Vec3> zeroSet;
  for (const auto& t : sphere.Simplices)
  {
    for (int i = 0; i < 8; ++i)
    {
      double s = u01(rng), r = u01(rng);
      if (s + r > 1.0)
      {
        s = 1.0 - s;
        r = 1.0 - r;
      }
      const Vec3 p = sphere.Vertices[t[0]] + s * (sphere.Vertices[t[1]] - sphere.Vertices[t[0]]) +
        r * (sphere.Vertices[t[2]] - sphere.Vertices[t[0]]);
      if (box->Value(p) > 0.0)
      {
        zeroSet.push_back(p);
      }
    }
  }
  // The inscribed radius of the mesh: box points nearer the center than
  // that are certainly inside the mesh.
  const double inscribed = mesh->Hierarchy()->Distance(Vec3::Zero());
  const int grid = 200;
  for (int face = 0; face < 3; ++face)
  {
    for (int i = 0; i <= grid; ++i)
    {
      for (int j = 0; j <= grid; ++j)
      {
        Vec3 p;
        p[face] = 0.0; // the faces of the box inside the sphere lie on the coordinate planes
        p[(face + 1) % 3] = 1.2 * i / grid;
        p[(face + 2) % 3] = 1.2 * j / grid;
        if (p.norm() < inscribed)
        {
          zeroSet.push_back(p);
        }
      }
    }
  }
  ASSERT_GT(zeroSet.size(), 50000u);
  int near = 0;
  for (const Vec3& x : UniformPoints<3>(400, 1.3, 23))
  {
    double sampled = std::numeric_limits<double>::infinity();
    for (const Vec3& z : zeroSet)
    {
      sampled = std::min(sampled, (x - z).squaredNorm());
    }
    sampled = std::sqrt(sampled);
    const double value = std::abs(csg.Value(x));
    EXPECT_LE(value, sampled + 1e-12) << "at " << x.transpose();
    // Not vacuous: mostly within the sampling resolution of the distance.
    near += value > sampled - 0.02;
  }
  EXPECT_GT(near, 300);
}

//------------------------------------------------------------------------------
// Walk on spheres through the implicit path (paper Sec. 5.1.3–5.1.4): the
// Laplace equation with harmonic boundary data, whose exact solution is the
// harmonic function itself (paper Eqn. 5; the same check as the mesh tests
// in TestWalkOnSpheresLaplace.cxx).
namespace
{
Calibration SolveLaplace(std::shared_ptr<const SignedDistanceFunction<3>> phi, const Field<3>& g,
  const std::vector<Vec3>& points, std::uint64_t seed)
{
  const auto values = std::make_shared<CallableBoundaryValues<3>>(
    [g](const Vec3& p, std::int64_t, double* out) { out[0] = g(p); }, 1);
  Boundary<3> boundary;
  boundary.SetGeometry(std::make_shared<ImplicitBoundaryGeometry<3>>(std::move(phi)), values);
  WalkSettings settings;
  settings.Epsilon = 1e-4 * boundary.Diagonal();
  const Calibration c =
    CheckEstimator<3>(boundary, settings, points, { g }, 512, seed)[0];
  EXPECT_EQ(c.EscapedFraction, 0.0);
  EXPECT_EQ(c.TruncatedFraction, 0.0);
  return c;
}
} // namespace

// The mesh sphere alone (only |φ| and the projection matter here).
TEST(MeshSignedDistance, WalkOnSpheresInMeshSphere)
{
  const auto phi = MakeFunction<3>(MakeIcosphere(3));
  ExpectCalibrated(
    SolveLaplace(phi, Field<3>(&ExpTrig), RandomPointsInBall<3>(200, 0.85, 31), 32), 200);
}

// The mesh sphere minus the box octant [0, 1.2]³: here the sign of the mesh
// decides which CSG operand is active. The boundary data is the Newton
// potential of a pole inside the removed box, harmonic in the domain but not
// in the whole sphere: a wrong sign lets walks ignore the box faces (the
// CSG value becomes the plain mesh distance inside the sphere), they end on
// the sphere only, and the estimate is that of the sphere problem, which
// differs.
TEST(MeshSignedDistance, WalkOnSpheresInCsgDomain)
{
  const auto mesh = MakeFunction<3>(MakeIcosphere(3));
  const auto box = std::make_shared<BoxDistance<3>>(Vec3::Constant(0.6), Vec3::Constant(0.6));
  const auto csg = std::make_shared<CsgDistance<3>>(CsgOperation::Difference, mesh, box);
  std::vector<Vec3> points;
  for (const Vec3& x : RandomPointsInBall<3>(400, 0.85, 33))
  {
    if (box->Value(x) > 0.1 && points.size() < 200)
    {
      points.push_back(x);
    }
  }
  ASSERT_EQ(points.size(), 200u);
  const Vec3 pole = Vec3::Constant(0.6);
  const Field<3> newton = [pole](const Vec3& x) { return 1.0 / (x - pole).norm(); };
  ExpectCalibrated(SolveLaplace(csg, newton, points, 34), 200);
}

// Clean, closed and consistently oriented meshes take the sign from the
// pseudonormal at the closest point instead of rays; both orientations work,
// and anything else (one flipped triangle, a soup, nested shells oriented
// alike) keeps the rays. Either way Value's sign is the rays' answer.
TEST(MeshSignedDistance, CleanMeshesTakeTheirSignFromPseudonormals)
{
  auto flipped = [](SimplexMesh<3> mesh, bool all) {
    for (std::size_t i = 0; i < mesh.Simplices.size(); ++i)
    {
      if (all || i == 17)
      {
        std::swap(mesh.Simplices[i][1], mesh.Simplices[i][2]);
      }
    }
    return mesh;
  };
  // A shell inside a shell, both with outward normals: for parity the gap
  // between them is inside and the inner ball outside, which the inner
  // shell's pseudonormals contradict.
  SimplexMesh<3> nested = MakeIcosphere(3);
  const SimplexMesh<3> inner = MakeIcosphere(2, 0.5);
  const auto offset = static_cast<std::int64_t>(nested.Vertices.size());
  nested.Vertices.insert(nested.Vertices.end(), inner.Vertices.begin(), inner.Vertices.end());
  for (auto t : inner.Simplices)
  {
    nested.Simplices.push_back({ t[0] + offset, t[1] + offset, t[2] + offset });
  }
  struct Case
  {
    const char* Name;
    SimplexMesh<3> Mesh;
    bool Clean;
  };
  const Case cases[] = { { "icosphere", MakeIcosphere(4), true },
    { "icosphere, normals in", flipped(MakeIcosphere(4), true), true },
    { "one triangle flipped", flipped(MakeIcosphere(4), false), false },
    { "soup", MakeSoupOf<3>(MakeIcosphere(3), false), false },
    { "nested shells oriented alike", nested, false } };
  const auto points = UniformPoints<3>(4000, 1.3, 21);
  for (const Case& c : cases)
  {
    const auto phi = MakeFunction<3>(c.Mesh);
    EXPECT_EQ(phi->SignFromPseudonormals(), c.Clean) << c.Name;
    int disagree = 0;
    for (const Vec3& x : points)
    {
      const double v = phi->Value(x);
      disagree += (v < 0.0) != phi->Inside(x) ? 1 : 0;
    }
    EXPECT_EQ(disagree, 0) << c.Name;
  }
  // A shell with a cavity oriented as a solid's (inner normals into the
  // cavity) is clean: both agree, and the cavity is outside.
  SimplexMesh<3> cavity = MakeIcosphere(3);
  const SimplexMesh<3> hole = flipped(MakeIcosphere(2, 0.5), true);
  const auto at = static_cast<std::int64_t>(cavity.Vertices.size());
  cavity.Vertices.insert(cavity.Vertices.end(), hole.Vertices.begin(), hole.Vertices.end());
  for (auto t : hole.Simplices)
  {
    cavity.Simplices.push_back({ t[0] + at, t[1] + at, t[2] + at });
  }
  const auto shell = MakeFunction<3>(cavity);
  EXPECT_TRUE(shell->SignFromPseudonormals());
  EXPECT_GT(shell->Value(Vec3(0.0, 0.0, 0.0)), 0.0);
  EXPECT_LT(shell->Value(Vec3(0.75, 0.0, 0.0)), 0.0);
  // 2D: the star polygon is clean.
  EXPECT_TRUE(MakeFunction<2>(MakeStar())->SignFromPseudonormals());
}
