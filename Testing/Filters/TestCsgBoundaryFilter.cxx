// vtkWalkOnSpheresSolver with a composite Boundary input combined by CSG
// (CsgOperation): unions, differences and smooth unions of meshes and
// implicit functions, in 3D and 2D, values from an expression or from each
// operand's own array, and the messages for unusable input.
//
// A harmonic function of the whole space cannot tell one domain from another
// (its values on ANY boundary extend to itself), so where the test is about
// the shape of the combined domain the exact solution is a Newton potential
// u = 1/|x − p| whose pole p lies in the part that the operation removes: a
// wrong operation or a wrong inside test puts p inside the domain, and the
// estimate no longer equals u there.
#include "vtkWalkOnSpheresSolver.h"

#include "vtkSignedDistanceSphere.h"

#include "VtkMessageCatcher.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkImageData.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

namespace
{
constexpr double kPi = 3.14159265358979323846;

// A sphere mesh (fine enough that its inscribed error is far below the
// walks' standard errors) with an optional constant point array "g".
vtkSmartPointer<vtkPolyData> SphereMesh(const double centre[3], double radius, double g = 0.0)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(centre[0], centre[1], centre[2]);
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(120);
  sphere->SetPhiResolution(120);
  sphere->Update();
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->DeepCopy(sphere->GetOutput());
  vtkNew<vtkDoubleArray> values;
  values->SetName("g");
  values->SetNumberOfTuples(mesh->GetNumberOfPoints());
  values->FillValue(g);
  mesh->GetPointData()->AddArray(values);
  return mesh;
}

// A closed polygon approximating a circle in the z = 0 plane (2D boundary).
vtkSmartPointer<vtkPolyData> CirclePolyline(double cx, double cy, double radius, int segments)
{
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(segments + 1);
  for (int i = 0; i < segments; ++i)
  {
    const double a = 2.0 * kPi * i / segments;
    lines->InsertCellPoint(points->InsertNextPoint(
      cx + radius * std::cos(a), cy + radius * std::sin(a), 0.0));
  }
  lines->InsertCellPoint(0);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  return poly;
}

vtkSmartPointer<vtkMultiBlockDataSet> Blocks(std::initializer_list<vtkDataObject*> blocks)
{
  auto mb = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  unsigned int i = 0;
  for (vtkDataObject* block : blocks)
  {
    mb->SetBlock(i++, block);
  }
  return mb;
}

// Up to `count` points uniform in [lo, hi]^3 (z = 0 for 2D) that `keep`
// accepts, fixed seed.
vtkSmartPointer<vtkPolyData> Points(int count, double lo, double hi, bool planar,
  const std::function<bool(const double*)>& keep)
{
  std::mt19937_64 engine(20261122);
  std::uniform_real_distribution<double> u(lo, hi);
  vtkNew<vtkPoints> points;
  for (int tries = 0; points->GetNumberOfPoints() < count && tries < 1000000; ++tries)
  {
    const double p[3] = { u(engine), u(engine), planar ? 0.0 : u(engine) };
    if (keep(p))
    {
      points->InsertNextPoint(p);
    }
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  return cloud;
}

double Distance(const double* a, const double* b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}

struct Result
{
  vtkSmartPointer<vtkDataArray> Mean, Variance;
  std::string Errors, Warnings;
};

Result Solve(vtkDataObject* boundary, vtkPolyData* probe,
  const std::function<void(vtkWalkOnSpheresSolver*)>& configure, int walks = 256)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  vtkNew<MessageCatcher> catcher;
  solver->AddObserver(vtkCommand::WarningEvent, catcher);
  solver->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  if (boundary)
  {
    solver->SetBoundaryData(boundary);
  }
  solver->SetProbeData(probe);
  solver->SetWalksPerPoint(walks);
  solver->SetSeed(11);
  configure(solver);
  solver->Update();
  Result r;
  r.Errors = catcher->Errors;
  r.Warnings = catcher->Warnings;
  if (auto* out = vtkDataSet::SafeDownCast(solver->GetOutput()))
  {
    r.Mean = out->GetPointData()->GetArray("Solution");
    if (!r.Mean)
    {
      r.Mean = out->GetPointData()->GetArray("g");
    }
    if (r.Mean)
    {
      r.Variance = out->GetPointData()->GetArray(
        (std::string(r.Mean->GetName()) + "_Variance").c_str());
    }
  }
  return r;
}

// |z| < 5 at every point and mean z² near 1 against `exact`.
void ExpectCalibrated(
  const Result& r, vtkPolyData* probe, const std::function<double(const double*)>& exact)
{
  ASSERT_EQ(r.Errors, "");
  ASSERT_NE(r.Mean, nullptr);
  ASSERT_NE(r.Variance, nullptr);
  const vtkIdType n = probe->GetNumberOfPoints();
  ASSERT_GT(n, 20);
  double sumZ2 = 0.0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double z =
      (r.Mean->GetTuple1(i) - exact(probe->GetPoint(i))) / std::sqrt(r.Variance->GetTuple1(i));
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
  }
  EXPECT_GT(sumZ2 / n, 0.5);
  EXPECT_LT(sumZ2 / n, 1.6);
}
} // namespace

// Two overlapping mesh spheres; the pole sits in the notch between them,
// outside both: an intersection, or a sign error, would change the answer.
TEST(CsgBoundaryFilter, UnionOfTwoMeshesMatchesNewtonPotential)
{
  const double a[3] = { -0.5, 0, 0 }, b[3] = { 0.5, 0, 0 }, pole[3] = { 0, 0.78, 0 };
  auto boundary = Blocks({ SphereMesh(a, 0.8), SphereMesh(b, 0.8) });
  auto probe = Points(60, -1.3, 1.3, false, [&](const double* p) {
    return std::max(Distance(p, a), Distance(p, b)) > 0.85 && // not only in the lens
      std::min(Distance(p, a), Distance(p, b)) < 0.7 && Distance(p, pole) > 0.3;
  });
  const Result r = Solve(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetBoundaryValueExpression("1/sqrt(x^2 + (y-0.78)^2 + z^2)");
  });
  ExpectCalibrated(r, probe, [&](const double* p) { return 1.0 / Distance(p, pole); });
}

// A mesh ball minus an implicit ball (the module's exact sphere distance)
// that holds the pole.
TEST(CsgBoundaryFilter, MeshMinusImplicitMatchesNewtonPotential)
{
  const double origin[3] = { 0, 0, 0 }, pole[3] = { 0, 0, 0.6 };
  auto boundary = Blocks({ SphereMesh(origin, 1.0) });
  vtkNew<vtkSignedDistanceSphere> removed;
  removed->SetCenter(0, 0, 0.6);
  removed->SetRadius(0.4);
  auto probe = Points(60, -1, 1, false,
    [&](const double* p) { return Distance(p, origin) < 0.9 && Distance(p, pole) > 0.5; });
  const Result r = Solve(boundary, probe, [&](vtkWalkOnSpheresSolver* s) {
    s->SetImplicitBoundary(removed);
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_DIFFERENCE);
    s->SetBoundaryValueExpression("1/sqrt(x^2 + y^2 + (z-0.6)^2)");
  });
  ExpectCalibrated(r, probe, [&](const double* p) { return 1.0 / Distance(p, pole); });
}

// Intersection of two mesh balls (a lens); the pole is in one ball but not
// in the other, so a union would contain it.
TEST(CsgBoundaryFilter, IntersectionOfTwoMeshesMatchesNewtonPotential)
{
  const double a[3] = { -0.4, 0, 0 }, b[3] = { 0.4, 0, 0 }, pole[3] = { 1.0, 0, 0 };
  auto boundary = Blocks({ SphereMesh(a, 1.0), SphereMesh(b, 1.0) });
  auto probe = Points(60, -1, 1, false,
    [&](const double* p) { return std::max(Distance(p, a), Distance(p, b)) < 0.9; });
  const Result r = Solve(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_INTERSECTION);
    s->SetBoundaryValueExpression("1/sqrt((x-1)^2 + y^2 + z^2)");
  });
  ExpectCalibrated(r, probe, [&](const double* p) { return 1.0 / Distance(p, pole); });
}

// A smooth union (blend radius 0.2) with a harmonic polynomial: whatever the
// blended shape, the walks must stop on it and take the right values there.
TEST(CsgBoundaryFilter, SmoothUnionStaysCalibrated)
{
  const double a[3] = { -0.5, 0, 0 }, b[3] = { 0.5, 0, 0 };
  auto boundary = Blocks({ SphereMesh(a, 0.7), SphereMesh(b, 0.7) });
  auto probe = Points(60, -1.2, 1.2, false,
    [&](const double* p) { return std::min(Distance(p, a), Distance(p, b)) < 0.6; });
  const Result r = Solve(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetCsgBlendRadius(0.2);
    s->SetBoundaryValueExpression("x*x - y*y + 0.5*z");
  });
  ExpectCalibrated(r, probe, [](const double* p) { return p[0] * p[0] - p[1] * p[1] + 0.5 * p[2]; });
}

// Without an expression, each operand's own array gives the values: two
// disjoint balls with g = 1 and g = 2 give exactly those, with no variance.
TEST(CsgBoundaryFilter, EachOperandKeepsItsOwnValues)
{
  const double a[3] = { -1.5, 0, 0 }, b[3] = { 1.5, 0, 0 };
  auto boundary = Blocks({ SphereMesh(a, 1.0, 1.0), SphereMesh(b, 1.0, 2.0) });
  auto probe = Points(40, -2.5, 2.5, false,
    [&](const double* p) { return std::min(Distance(p, a), Distance(p, b)) < 0.9; });
  const Result r = Solve(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "g");
  }, 16);
  ASSERT_EQ(r.Errors, "");
  ASSERT_NE(r.Mean, nullptr);
  for (vtkIdType i = 0; i < probe->GetNumberOfPoints(); ++i)
  {
    const double expected = probe->GetPoint(i)[0] < 0.0 ? 1.0 : 2.0;
    EXPECT_DOUBLE_EQ(r.Mean->GetTuple1(i), expected) << "point " << i;
  }
}

// 2D: the union of two closed polylines (disks), with the pole in the notch.
TEST(CsgBoundaryFilter, UnionOfTwoPolylinesIn2D)
{
  const double a[3] = { -0.5, 0, 0 }, b[3] = { 0.5, 0, 0 }, pole[3] = { 0, 0.78, 0 };
  auto boundary = Blocks({ CirclePolyline(-0.5, 0, 0.8, 2048), CirclePolyline(0.5, 0, 0.8, 2048) });
  auto probe = Points(60, -1.3, 1.3, true, [&](const double* p) {
    return std::max(Distance(p, a), Distance(p, b)) > 0.85 &&
      std::min(Distance(p, a), Distance(p, b)) < 0.7 && Distance(p, pole) > 0.3;
  });
  // log|x − p| is the 2D Newton potential.
  const Result r = Solve(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetBoundaryValueExpression("ln(sqrt(x^2 + (y-0.78)^2))");
  });
  ExpectCalibrated(r, probe, [&](const double* p) { return std::log(Distance(p, pole)); });
}

// Without CSG, the blocks of a composite boundary are one polygon soup: the
// same numbers as the blocks appended into one vtkPolyData.
TEST(CsgBoundaryFilter, BlocksWithoutCsgAreOneSoup)
{
  const double a[3] = { -1.5, 0, 0 }, b[3] = { 1.5, 0, 0 };
  auto ma = SphereMesh(a, 1.0, 1.0), mb = SphereMesh(b, 1.0, 2.0);
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(ma);
  append->AddInputData(mb);
  append->Update();
  auto probe = Points(20, -2.5, 2.5, false, [](const double*) { return true; });
  auto configure = [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "g");
  };
  const Result blocks = Solve(Blocks({ ma, mb }), probe, configure, 32);
  const Result single = Solve(append->GetOutput(), probe, configure, 32);
  ASSERT_EQ(blocks.Errors, "");
  ASSERT_EQ(single.Errors, "");
  ASSERT_NE(blocks.Mean, nullptr);
  ASSERT_NE(single.Mean, nullptr);
  for (vtkIdType i = 0; i < probe->GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(blocks.Mean->GetTuple1(i), single.Mean->GetTuple1(i)) << "point " << i;
  }
}

TEST(CsgBoundaryFilter, ErrorsNameTheProblem)
{
  const double origin[3] = { 0, 0, 0 };
  auto probe = Points(5, -0.3, 0.3, false, [](const double*) { return true; });
  vtkNew<vtkSignedDistanceSphere> removed;
  removed->SetRadius(0.2);

  // An implicit operand has no array of its own.
  Result r = Solve(Blocks({ SphereMesh(origin, 1.0, 1.0) }), probe, [&](vtkWalkOnSpheresSolver* s) {
    s->SetImplicitBoundary(removed);
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_DIFFERENCE);
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "g");
  });
  EXPECT_NE(r.Errors.find("BoundaryValueExpression"), std::string::npos) << r.Errors;

  // A block that is not a surface.
  vtkNew<vtkImageData> image;
  image->SetDimensions(2, 2, 2);
  r = Solve(Blocks({ SphereMesh(origin, 1.0, 1.0), image }), probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetBoundaryValueExpression("1");
  });
  EXPECT_NE(r.Errors.find("vtkPolyData"), std::string::npos) << r.Errors;

  // A composite boundary with no block at all.
  r = Solve(Blocks({}), probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetCsgOperation(vtkWalkOnSpheresSolver::CSG_UNION);
    s->SetBoundaryValueExpression("1");
  });
  EXPECT_NE(r.Errors.find("no vtkPolyData"), std::string::npos) << r.Errors;
}
