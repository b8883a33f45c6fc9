// Insulating sheets (MixedBoundary's two-sided primitives: the domain on both
// sides, no flux through either) against a closed form with a slit: in the
// square [−1, 1]² (2D) or the cube [−1, 1]³ (3D) with Dirichlet data, a
// sheet along the half-plane y = 0, x > 0; u = √r cos(θ/2), θ in [0, 2π)
// from the positive x axis and r = √(x² + y²), is harmonic off the sheet,
// has ∂u/∂n = 0 on both of its sides and jumps by 2√r across it. Every
// point |z| < 5, mean z² in [0.7, 1.4], no back-face hits and no point
// taken for outside; the same data without the sheet (a plain Dirichlet
// problem, whose solution is continuous) fails the check.
#include "MixedShapes.h"
#include "StarChecks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

namespace insulating_sheet_tests
{
using namespace gridfree;
using namespace gridfree::testing;

template <int DIM>
double SlitSolution(const Vec<DIM>& x)
{
  double theta = std::atan2(x[1], x[0]);
  if (theta < 0.0)
  {
    theta += 2.0 * M_PI;
  }
  return std::sqrt(std::hypot(x[0], x[1])) * std::cos(0.5 * theta);
}

// The box's boundary (Dirichlet, n cuts a side) and the sheet y = 0,
// 0 <= x <= 1 (across the box in z), `cuts` segments or cuts × 2·cuts
// squares of two triangles.
template <int DIM>
SimplexMesh<DIM> BoxWithSheet(int n, int cuts, std::vector<BoundaryCondition>& conditions)
{
  SimplexMesh<DIM> mesh = MakeBlockShape<DIM>({ Cell<DIM>{} }, n, 2.0, Vec<DIM>::Constant(-1.0));
  conditions.assign(mesh.Simplices.size(), BoundaryCondition::Dirichlet);
  const std::int64_t first = static_cast<std::int64_t>(mesh.Vertices.size());
  if constexpr (DIM == 2)
  {
    for (int i = 0; i <= cuts; ++i)
    {
      mesh.Vertices.push_back(Vec2(static_cast<double>(i) / cuts, 0.0));
    }
    for (int i = 0; i < cuts; ++i)
    {
      mesh.Simplices.push_back({ first + i, first + i + 1 });
    }
  }
  else
  {
    const int along = 2 * cuts;
    for (int j = 0; j <= along; ++j)
    {
      for (int i = 0; i <= cuts; ++i)
      {
        mesh.Vertices.push_back(Vec3(static_cast<double>(i) / cuts, 0.0, -1.0 + 2.0 * j / along));
      }
    }
    auto at = [&](int i, int j) { return first + j * (cuts + 1) + i; };
    for (int j = 0; j < along; ++j)
    {
      for (int i = 0; i < cuts; ++i)
      {
        mesh.Simplices.push_back({ at(i, j), at(i + 1, j), at(i + 1, j + 1) });
        mesh.Simplices.push_back({ at(i, j), at(i + 1, j + 1), at(i, j + 1) });
      }
    }
  }
  conditions.resize(mesh.Simplices.size(), BoundaryCondition::InsulatingSheet);
  return mesh;
}

// The mixed boundary of the mesh: u on the Dirichlet part, flux 0 on the
// sheet; `withSheet` false leaves the sheet out.
template <int DIM>
MixedBoundary<DIM> SlitBoundary(const SimplexMesh<DIM>& mesh,
  const std::vector<BoundaryCondition>& conditions, bool withSheet)
{
  MeshPart<DIM> d, r;
  const std::vector<std::array<std::int64_t, DIM>> prims(mesh.Simplices.begin(), mesh.Simplices.end());
  SplitByCondition<DIM>(mesh.Vertices, prims, conditions, d, r);
  auto dirichlet = std::make_shared<Boundary<DIM>>();
  dirichlet->SetMesh(d.Vertices, d.Primitives,
    std::make_shared<CallableBoundaryValues<DIM>>(
      [](const Vec<DIM>& z, std::int64_t, double* out) { out[0] = SlitSolution<DIM>(z); }, 1));
  std::shared_ptr<Boundary<DIM>> sheet;
  std::vector<std::uint8_t> twoSided;
  if (withSheet)
  {
    sheet = std::make_shared<Boundary<DIM>>();
    sheet->SetMesh(r.Vertices, r.Primitives,
      std::make_shared<CallableBoundaryValues<DIM>>(
        [](const Vec<DIM>&, std::int64_t, double* out) { out[0] = 0.0; }, 1));
    twoSided.assign(r.Primitives.size(), 1);
  }
  MixedBoundary<DIM> mixed;
  mixed.Set(dirichlet, sheet, {}, true, twoSided);
  return mixed;
}

// Points in the box at least 0.05 from its sides and from the sheet.
template <int DIM>
std::vector<Vec<DIM>> PointsOffTheSheet(int count, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.95, 0.95);
  std::vector<Vec<DIM>> points;
  while (static_cast<int>(points.size()) < count)
  {
    Vec<DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = u(rng);
    }
    if (p[0] > -0.05 && std::abs(p[1]) < 0.05)
    {
      continue;
    }
    points.push_back(p);
  }
  return points;
}

// The sheet problem at `points`; `outside` counts those the boundary's
// inside test misses.
template <int DIM>
Calibration Solve(const MixedBoundary<DIM>& b, const std::vector<Vec<DIM>>& points, int walks,
  std::uint64_t& backHits, int& outside)
{
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  outside = 0;
  for (const Vec<DIM>& p : points)
  {
    outside += b.Inside(p) ? 0 : 1;
  }
  return CalibrateStars<DIM>(b, settings, points, SlitSolution<DIM>, walks, 2027, backHits);
}

template <int DIM>
void ExpectSheetSolved(int n, int cuts, int count, int walks)
{
  std::vector<BoundaryCondition> conditions;
  const SimplexMesh<DIM> mesh = BoxWithSheet<DIM>(n, cuts, conditions);
  const auto points = PointsOffTheSheet<DIM>(count, 5 + DIM);
  std::uint64_t backHits = 0;
  int outside = 0;
  const MixedBoundary<DIM> withSheet = SlitBoundary<DIM>(mesh, conditions, true);
  ASSERT_TRUE(withSheet.HasTwoSided());
  const Calibration c = Solve<DIM>(withSheet, points, walks, backHits, outside);
  std::printf("insulating sheet %dD: mean z² %.3f, max |z| %.2f\n", DIM, c.MeanZ2, c.MaxAbsZ);
  ExpectCalibrated(c, count);
  EXPECT_EQ(backHits, 0u);
  EXPECT_EQ(outside, 0);
  const Calibration without =
    Solve<DIM>(SlitBoundary<DIM>(mesh, conditions, false), points, walks, backHits, outside);
  std::printf("sheet left out %dD: mean z² %.3f, max |z| %.2f\n", DIM, without.MeanZ2,
    without.MaxAbsZ);
  EXPECT_TRUE(without.MeanZ2 > 2.0 || without.MaxAbsZ > 5.0);
}

TEST(InsulatingSheets, SlitInASquare2D) { ExpectSheetSolved<2>(16, 20, 200, 512); }
TEST(InsulatingSheets, SlitInACube3D) { ExpectSheetSolved<3>(8, 8, 150, 128); }
} // namespace insulating_sheet_tests
