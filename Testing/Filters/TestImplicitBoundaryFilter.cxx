// vtkWalkOnSpheresSolver with an implicit boundary (a vtkImplicitFunction):
// accuracy against closed forms, agreement with the same sphere given as a
// mesh, values sampled from a mesh, boolean combinations, and the messages
// for missing values and a too small Lipschitz bound.
//
// Every boundary value here is the restriction of a harmonic function u of
// the whole space, so the exact solution in ANY domain is u itself: the
// domain's shape (a sphere, a union of spheres) cannot hide an error.
#include "vtkWalkOnSpheresSolver.h"

#include "VtkMessageCatcher.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkImplicitBoolean.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphere.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

namespace
{
double Harmonic(const double p[3])
{
  return p[0] * p[0] - p[1] * p[1] + 0.5 * p[2];
}
const char* HarmonicExpression = "x*x - y*y + 0.5*z";

// `count` points drawn uniformly in the ball (centre, radius), fixed seed.
vtkSmartPointer<vtkPolyData> BallPoints(int count, const double centre[3], double radius)
{
  std::mt19937_64 engine(20261122);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  vtkNew<vtkPoints> points;
  while (points->GetNumberOfPoints() < count)
  {
    const double p[3] = { u(engine), u(engine), u(engine) };
    if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0)
    {
      points->InsertNextPoint(
        centre[0] + radius * p[0], centre[1] + radius * p[1], centre[2] + radius * p[2]);
    }
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  return cloud;
}

// A unit sphere mesh carrying the harmonic function as "T".
vtkSmartPointer<vtkPolyData> SphereMesh()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(160);
  sphere->SetPhiResolution(160);
  sphere->Update();
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->DeepCopy(sphere->GetOutput());
  vtkNew<vtkDoubleArray> t;
  t->SetName("T");
  t->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    t->SetValue(i, Harmonic(mesh->GetPoint(i)));
  }
  mesh->GetPointData()->AddArray(t);
  return mesh;
}

struct Estimate
{
  vtkSmartPointer<vtkDataArray> Mean, Variance;
};

Estimate Solve(const std::function<void(vtkWalkOnSpheresSolver*)>& configure, vtkPolyData* probe,
  const char* name, std::string* warnings = nullptr)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  vtkNew<MessageCatcher> catcher;
  solver->AddObserver(vtkCommand::WarningEvent, catcher);
  solver->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->SetProbeData(probe);
  solver->SetWalksPerPoint(256);
  solver->SetSeed(7);
  configure(solver);
  solver->Update();
  EXPECT_EQ(catcher->Errors, "");
  if (warnings)
  {
    *warnings = catcher->Warnings;
  }
  auto* out = vtkDataSet::SafeDownCast(solver->GetOutput());
  Estimate e;
  e.Mean = out->GetPointData()->GetArray(name);
  e.Variance = out->GetPointData()->GetArray((std::string(name) + "_Variance").c_str());
  return e;
}

// |z| < 5 everywhere and mean z² near 1 against the exact harmonic function.
void ExpectCalibrated(const Estimate& e, vtkPolyData* probe)
{
  ASSERT_NE(e.Mean, nullptr);
  ASSERT_NE(e.Variance, nullptr);
  double sumZ2 = 0.0;
  const vtkIdType n = probe->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double exact = Harmonic(probe->GetPoint(i));
    const double z = (e.Mean->GetTuple1(i) - exact) / std::sqrt(e.Variance->GetTuple1(i));
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
  }
  EXPECT_GT(sumZ2 / n, 0.6);
  EXPECT_LT(sumZ2 / n, 1.5);
}
} // namespace

TEST(ImplicitBoundaryFilter, SphereFunctionMatchesClosedForm)
{
  const double origin[3] = { 0, 0, 0 };
  auto probe = BallPoints(60, origin, 0.85);
  vtkNew<vtkSphere> sphere; // φ = |x|² − 1: slope 2|x| ≤ 2 inside
  sphere->SetRadius(1.0);
  std::string warnings;
  const Estimate e = Solve(
    [&](vtkWalkOnSpheresSolver* s) {
      s->SetImplicitBoundary(sphere);
      s->SetLipschitzBound(2.0);
      s->SetBoundaryValueExpression(HarmonicExpression);
    },
    probe, "Solution", &warnings);
  EXPECT_EQ(warnings, "");
  ExpectCalibrated(e, probe);
}

TEST(ImplicitBoundaryFilter, SphereAsMeshAndAsFunctionAgree)
{
  const double origin[3] = { 0, 0, 0 };
  auto probe = BallPoints(60, origin, 0.85);
  vtkNew<vtkSphere> sphere;
  sphere->SetRadius(1.0);
  const Estimate implicit = Solve(
    [&](vtkWalkOnSpheresSolver* s) {
      s->SetImplicitBoundary(sphere);
      s->SetLipschitzBound(2.0);
      s->SetBoundaryValueExpression(HarmonicExpression);
    },
    probe, "Solution");
  auto mesh = SphereMesh();
  const Estimate meshed = Solve(
    [&](vtkWalkOnSpheresSolver* s) {
      s->SetBoundaryData(mesh);
      s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
      s->SetSeed(8); // independent walks
    },
    probe, "T");
  double sumZ2 = 0.0;
  for (vtkIdType i = 0; i < probe->GetNumberOfPoints(); ++i)
  {
    const double z = (implicit.Mean->GetTuple1(i) - meshed.Mean->GetTuple1(i)) /
      std::sqrt(implicit.Variance->GetTuple1(i) + meshed.Variance->GetTuple1(i));
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
  }
  EXPECT_GT(sumZ2 / probe->GetNumberOfPoints(), 0.6);
  EXPECT_LT(sumZ2 / probe->GetNumberOfPoints(), 1.5);
}

TEST(ImplicitBoundaryFilter, ValuesSampledFromAMesh)
{
  const double origin[3] = { 0, 0, 0 };
  auto probe = BallPoints(60, origin, 0.85);
  vtkNew<vtkSphere> sphere;
  sphere->SetRadius(1.0);
  auto mesh = SphereMesh();
  const Estimate e = Solve(
    [&](vtkWalkOnSpheresSolver* s) {
      s->SetImplicitBoundary(sphere);
      s->SetLipschitzBound(2.0);
      s->SetBoundaryData(mesh); // values only: each boundary point takes the nearest mesh value
      s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    },
    probe, "T");
  ExpectCalibrated(e, probe);
}

TEST(ImplicitBoundaryFilter, UnionOfTwoSpheres)
{
  // Two overlapping balls of radius 0.6: φ = min(|x − a|² − r², |x − b|² − r²)
  // with slope ≤ 2r = 1.2 inside; probe points in both lobes and the neck.
  vtkNew<vtkSphere> left, right;
  left->SetCenter(-0.4, 0.0, 0.0);
  left->SetRadius(0.6);
  right->SetCenter(0.4, 0.0, 0.0);
  right->SetRadius(0.6);
  vtkNew<vtkImplicitBoolean> both;
  both->SetOperationTypeToUnion();
  both->AddFunction(left);
  both->AddFunction(right);
  const double a[3] = { -0.4, 0.0, 0.0 }, b[3] = { 0.4, 0.0, 0.0 };
  auto probe = BallPoints(30, a, 0.45);
  auto more = BallPoints(30, b, 0.45);
  for (vtkIdType i = 0; i < more->GetNumberOfPoints(); ++i)
  {
    probe->GetPoints()->InsertNextPoint(more->GetPoint(i));
  }
  std::string warnings;
  const Estimate e = Solve(
    [&](vtkWalkOnSpheresSolver* s) {
      s->SetImplicitBoundary(both);
      s->SetLipschitzBound(1.2);
      s->SetBoundaryValueExpression(HarmonicExpression);
    },
    probe, "Solution", &warnings);
  EXPECT_EQ(warnings, "");
  ExpectCalibrated(e, probe);
}

TEST(ImplicitBoundaryFilter, MessagesForBadSettings)
{
  const double origin[3] = { 0, 0, 0 };
  auto probe = BallPoints(4, origin, 0.5);
  vtkNew<vtkSphere> sphere;
  sphere->SetRadius(1.0);
  // The errors one run reports.
  auto errorsOf = [&](const std::function<void(vtkWalkOnSpheresSolver*)>& configure) {
    vtkNew<vtkWalkOnSpheresSolver> solver;
    vtkNew<MessageCatcher> catcher;
    solver->AddObserver(vtkCommand::ErrorEvent, catcher);
    solver->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
    solver->SetImplicitBoundary(sphere);
    solver->SetProbeData(probe);
    configure(solver);
    solver->Update();
    return catcher->Errors;
  };
  {
    // No values at all: an error, not a crash.
    const std::string errors = errorsOf([](vtkWalkOnSpheresSolver*) {});
    EXPECT_NE(errors.find("has no values"), std::string::npos) << errors;
  }
  {
    // |x|² − 1 has slope up to 2 inside the unit ball: L = 1 is too small.
    std::string warnings;
    Solve(
      [&](vtkWalkOnSpheresSolver* s) {
        s->SetImplicitBoundary(sphere);
        s->SetBoundaryValueExpression(HarmonicExpression);
        s->SetWalksPerPoint(4);
      },
      probe, "Solution", &warnings);
    EXPECT_NE(warnings.find("LipschitzBound"), std::string::npos) << warnings;
  }
  {
    // A broken expression is an error naming it.
    const std::string errors = errorsOf([](vtkWalkOnSpheresSolver* s) {
      s->SetLipschitzBound(2.0);
      s->SetBoundaryValueExpression("x*(");
    });
    EXPECT_NE(errors.find("x*("), std::string::npos) << errors;
  }
}
