// The VTK signed distance primitives (vtkSignedDistance*): the same numbers
// as the core's exact distances, their bounds and Lipschitz constants with
// and without a Transform, invalid parameters (NaN, no crash, a solver
// error), vtkImplicitBoolean trees against the core's CsgDistance, and the
// solver on them against closed forms.
//
// Every boundary value in the solver tests is the restriction of a harmonic
// function u of the whole space, so the exact solution in ANY domain is u
// itself: the domain's shape (a ball, a union, a difference) cannot hide an
// error.
#include "vtkSignedDistanceBox.h"
#include "vtkSignedDistanceCapsule.h"
#include "vtkSignedDistanceCylinder.h"
#include "vtkSignedDistancePlane.h"
#include "vtkSignedDistanceRoundedBox.h"
#include "vtkSignedDistanceSphere.h"
#include "vtkSignedDistanceTorus.h"
#include "vtkWalkOnSpheresSolver.h"

#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/SignedDistanceFunctions.h>

#include "VtkMessageCatcher.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkImplicitBoolean.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphere.h"
#include "vtkTransform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace
{
using gridfree::Vec3;

// Random points in [-2.5, 2.5]³ (fixed seed) plus points where the
// functions have no gradient or change formula: centers, axes, the origin.
std::vector<Vec3> TestPoints()
{
  std::vector<Vec3> points = { Vec3(0, 0, 0), Vec3(0.3, -0.2, 0.1), Vec3(0.3, -0.2, 1.5),
    Vec3(1.0, 1.0, 1.0), Vec3(-0.5, 0.0, 0.0), Vec3(0.5, 0.0, 0.0) };
  std::mt19937_64 engine(424242);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int i = 0; i < 3000; ++i)
  {
    points.emplace_back(u(engine), u(engine), u(engine));
  }
  return points;
}

// Value (and gradient) of the VTK function equal the core's, bit for bit.
void ExpectSameAsCore(vtkImplicitFunction* f, const gridfree::SignedDistanceFunction<3>& core,
  bool compareGradient = true)
{
  SCOPED_TRACE(f->GetClassName());
  int mismatches = 0;
  for (const Vec3& p : TestPoints())
  {
    double x[3] = { p[0], p[1], p[2] };
    const double value = f->FunctionValue(x);
    Vec3 expected = core.Gradient(p);
    double g[3] = { expected[0], expected[1], expected[2] };
    if (compareGradient)
    {
      f->FunctionGradient(x, g);
    }
    const bool same = value == core.Value(p) && g[0] == expected[0] && g[1] == expected[1] &&
      g[2] == expected[2];
    if (!same && ++mismatches <= 5)
    {
      ADD_FAILURE() << "at (" << p.transpose() << "): value " << value << " vs " << core.Value(p)
                    << ", gradient (" << g[0] << ", " << g[1] << ", " << g[2] << ") vs ("
                    << expected.transpose() << ")";
    }
  }
  EXPECT_EQ(mismatches, 0);
}

void ExpectBounds(vtkSignedDistancePrimitive* f, const gridfree::BoundingBox<3>& expected)
{
  SCOPED_TRACE(f->GetClassName());
  double b[6] = { 0, 0, 0, 0, 0, 0 };
  ASSERT_TRUE(f->GetZeroSetBounds(b));
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_DOUBLE_EQ(b[2 * k], expected.Min[k]);
    EXPECT_DOUBLE_EQ(b[2 * k + 1], expected.Max[k]);
  }
}

double Harmonic(const double p[3])
{
  return p[0] * p[0] - p[1] * p[1] + 0.5 * p[2];
}
const char* HarmonicExpression = "x*x - y*y + 0.5*z";

// `count` points drawn uniformly in the ball (centre, radius) where `keep`
// holds, fixed seed.
vtkSmartPointer<vtkPolyData> BallPoints(int count, const Vec3& centre, double radius,
  const std::function<bool(const Vec3&)>& keep = nullptr)
{
  std::mt19937_64 engine(20261123);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  vtkNew<vtkPoints> points;
  while (points->GetNumberOfPoints() < count)
  {
    const Vec3 d(u(engine), u(engine), u(engine));
    const Vec3 p = centre + radius * d;
    if (d.squaredNorm() <= 1.0 && (!keep || keep(p)))
    {
      points->InsertNextPoint(p[0], p[1], p[2]);
    }
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  return cloud;
}

void Append(vtkPolyData* to, vtkPolyData* from)
{
  for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i)
  {
    to->GetPoints()->InsertNextPoint(from->GetPoint(i));
  }
}

// Solves u = harmonic on the implicit boundary f at the probe's points and
// checks |z| < 5 at every point, mean z² in [0.6, 1.5], and no message.
void ExpectSolverCalibrated(vtkImplicitFunction* f, vtkPolyData* probe, double lipschitz = 1.0)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  vtkNew<MessageCatcher> catcher;
  solver->AddObserver(vtkCommand::WarningEvent, catcher);
  solver->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->SetImplicitBoundary(f);
  solver->SetLipschitzBound(lipschitz);
  solver->SetBoundaryValueExpression(HarmonicExpression);
  solver->SetProbeData(probe);
  solver->SetWalksPerPoint(512);
  solver->SetSeed(11);
  solver->Update();
  EXPECT_EQ(catcher->Errors, "");
  EXPECT_EQ(catcher->Warnings, "");
  auto* out = vtkDataSet::SafeDownCast(solver->GetOutput());
  vtkDataArray* mean = out->GetPointData()->GetArray("Solution");
  vtkDataArray* variance = out->GetPointData()->GetArray("Solution_Variance");
  ASSERT_NE(mean, nullptr);
  ASSERT_NE(variance, nullptr);
  double sumZ2 = 0.0;
  const vtkIdType n = probe->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double exact = Harmonic(probe->GetPoint(i));
    const double z = (mean->GetTuple1(i) - exact) / std::sqrt(variance->GetTuple1(i));
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
  }
  EXPECT_GT(sumZ2 / n, 0.6);
  EXPECT_LT(sumZ2 / n, 1.5);
}

// The errors of one solver run on f.
std::string SolverErrors(vtkImplicitFunction* f)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  vtkNew<MessageCatcher> catcher;
  solver->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->SetImplicitBoundary(f);
  solver->SetBoundaryValueExpression(HarmonicExpression);
  solver->SetProbeData(BallPoints(4, Vec3::Zero(), 0.1));
  solver->SetWalksPerPoint(4);
  solver->Update();
  return catcher->Errors;
}
} // namespace

TEST(SignedDistancePrimitives, SameNumbersAsTheCore)
{
  vtkNew<vtkSignedDistanceSphere> sphere;
  sphere->SetCenter(0.3, -0.2, 0.1);
  sphere->SetRadius(1.1);
  ExpectSameAsCore(sphere, gridfree::SphereDistance<3>(Vec3(0.3, -0.2, 0.1), 1.1));

  vtkNew<vtkSignedDistanceBox> box;
  box->SetCenter(0.3, -0.2, 0.1);
  box->SetHalfExtents(1.0, 0.5, 0.25);
  ExpectSameAsCore(box, gridfree::BoxDistance<3>(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 0.5, 0.25)));

  vtkNew<vtkSignedDistanceRoundedBox> rounded;
  rounded->SetCenter(0.3, -0.2, 0.1);
  rounded->SetHalfExtents(1.0, 0.5, 0.25);
  rounded->SetRounding(0.2);
  ExpectSameAsCore(
    rounded, gridfree::RoundedBoxDistance<3>(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 0.5, 0.25), 0.2));
  // Rounding beyond the smallest half extent is clamped, as in the core.
  rounded->SetRounding(7.0);
  ExpectSameAsCore(
    rounded, gridfree::RoundedBoxDistance<3>(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 0.5, 0.25), 7.0));

  vtkNew<vtkSignedDistanceTorus> torus;
  torus->SetCenter(0.3, -0.2, 0.1);
  torus->SetAxis(1.0, 2.0, -0.5); // not unit: normalized like the core does
  torus->SetMajorRadius(1.2);
  torus->SetMinorRadius(0.4);
  ExpectSameAsCore(
    torus, gridfree::TorusDistance(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 2.0, -0.5), 1.2, 0.4));

  vtkNew<vtkSignedDistanceCylinder> cylinder;
  cylinder->SetCenter(0.3, -0.2, 0.1);
  cylinder->SetAxis(0.0, 3.0, 4.0);
  cylinder->SetRadius(0.7);
  cylinder->SetHalfHeight(1.3);
  ExpectSameAsCore(
    cylinder, gridfree::CylinderDistance(Vec3(0.3, -0.2, 0.1), Vec3(0.0, 3.0, 4.0), 0.7, 1.3));

  vtkNew<vtkSignedDistanceCapsule> capsule;
  capsule->SetPoint1(-0.5, 0.0, 0.0);
  capsule->SetPoint2(0.5, 0.4, 1.0);
  capsule->SetRadius(0.6);
  ExpectSameAsCore(
    capsule, gridfree::CapsuleDistance<3>(Vec3(-0.5, 0.0, 0.0), Vec3(0.5, 0.4, 1.0), 0.6));

  vtkNew<vtkSignedDistancePlane> plane;
  plane->SetOrigin(0.3, -0.2, 0.1);
  plane->SetNormal(1.0, 1.0, 2.0);
  ExpectSameAsCore(plane, gridfree::PlaneDistance<3>(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 1.0, 2.0)));

  // The defaults are valid solids.
  for (vtkSignedDistancePrimitive* f : std::vector<vtkSignedDistancePrimitive*>{
         vtkSignedDistanceSphere::New(), vtkSignedDistanceBox::New(),
         vtkSignedDistanceRoundedBox::New(), vtkSignedDistanceTorus::New(),
         vtkSignedDistanceCylinder::New(), vtkSignedDistanceCapsule::New(),
         vtkSignedDistancePlane::New() })
  {
    EXPECT_TRUE(f->HasValidParameters()) << f->GetClassName() << ": " << f->GetParameterError();
    EXPECT_EQ(f->GetLipschitzConstant(), 1.0);
    f->Delete();
  }
}

TEST(SignedDistancePrimitives, ZeroSetBounds)
{
  vtkNew<vtkSignedDistanceSphere> sphere;
  sphere->SetCenter(1.0, 2.0, 3.0);
  sphere->SetRadius(0.5);
  ExpectBounds(sphere, gridfree::BoundingBox<3>(Vec3(0.5, 1.5, 2.5), Vec3(1.5, 2.5, 3.5)));

  vtkNew<vtkSignedDistanceBox> box;
  box->SetCenter(1.0, 2.0, 3.0);
  box->SetHalfExtents(0.1, 0.2, 0.3);
  ExpectBounds(box, gridfree::BoundingBox<3>(Vec3(0.9, 1.8, 2.7), Vec3(1.1, 2.2, 3.3)));

  vtkNew<vtkSignedDistanceRoundedBox> rounded;
  rounded->SetHalfExtents(0.1, 0.2, 0.3);
  rounded->SetRounding(0.05); // the outer box does not change
  ExpectBounds(rounded, gridfree::BoundingBox<3>(Vec3(-0.1, -0.2, -0.3), Vec3(0.1, 0.2, 0.3)));

  vtkNew<vtkSignedDistanceTorus> torus; // ring in the xy-plane
  torus->SetMajorRadius(2.0);
  torus->SetMinorRadius(0.5);
  ExpectBounds(torus, gridfree::BoundingBox<3>(Vec3(-2.5, -2.5, -0.5), Vec3(2.5, 2.5, 0.5)));
  torus->SetAxis(1.0, 1.0, 0.0);
  ExpectBounds(torus, gridfree::TorusDistance(Vec3::Zero(), Vec3(1, 1, 0), 2.0, 0.5).Bounds());

  vtkNew<vtkSignedDistanceCylinder> cylinder; // along z
  cylinder->SetRadius(0.5);
  cylinder->SetHalfHeight(2.0);
  ExpectBounds(cylinder, gridfree::BoundingBox<3>(Vec3(-0.5, -0.5, -2.0), Vec3(0.5, 0.5, 2.0)));

  vtkNew<vtkSignedDistanceCapsule> capsule;
  capsule->SetPoint1(0.0, 0.0, 0.0);
  capsule->SetPoint2(1.0, 2.0, 0.0);
  capsule->SetRadius(0.5);
  ExpectBounds(capsule, gridfree::BoundingBox<3>(Vec3(-0.5, -0.5, -0.5), Vec3(1.5, 2.5, 0.5)));

  vtkNew<vtkSignedDistancePlane> plane;
  double untouched[6] = { 7, 7, 7, 7, 7, 7 };
  EXPECT_FALSE(plane->GetZeroSetBounds(untouched));
  EXPECT_EQ(untouched[0], 7.0);
}

TEST(SignedDistancePrimitives, TransformIsHonoured)
{
  // FunctionValue(x) = φ(T x): with T x = 2 x + (1, 0, 0) the unit sphere at
  // (1, 0, 0) is, in world coordinates, the sphere of radius 1/2 at the
  // origin, and the slope doubles.
  vtkNew<vtkSignedDistanceSphere> sphere;
  sphere->SetCenter(1.0, 0.0, 0.0);
  sphere->SetRadius(1.0);
  vtkNew<vtkTransform> transform;
  transform->Translate(1.0, 0.0, 0.0);
  transform->Scale(2.0, 2.0, 2.0);
  sphere->SetTransform(transform);
  double x[3] = { 0.1, 0.2, -0.3 };
  double local[3] = { 1.2, 0.4, -0.6 };
  EXPECT_DOUBLE_EQ(sphere->FunctionValue(x), sphere->EvaluateFunction(local));
  EXPECT_NEAR(sphere->FunctionValue(x), 2.0 * (std::sqrt(0.14) - 0.5), 1e-14);
  EXPECT_NEAR(sphere->GetLipschitzConstant(), 2.0, 1e-12);
  double b[6];
  ASSERT_TRUE(sphere->GetZeroSetBounds(b));
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_NEAR(b[2 * k], -0.5, 1e-12);
    EXPECT_NEAR(b[2 * k + 1], 0.5, 1e-12);
  }

  // A rigid motion keeps the constant 1; a rotated box's world bounds hold
  // the rotated corners.
  vtkNew<vtkSignedDistanceBox> box;
  box->SetHalfExtents(1.0, 1.0, 1.0);
  vtkNew<vtkTransform> rotation;
  rotation->RotateZ(45.0);
  box->SetTransform(rotation);
  EXPECT_NEAR(box->GetLipschitzConstant(), 1.0, 1e-12);
  ASSERT_TRUE(box->GetZeroSetBounds(b));
  EXPECT_NEAR(b[1], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(b[5], 1.0, 1e-12);

  // A singular transform has no bounded preimage to report.
  vtkNew<vtkTransform> flat;
  flat->Scale(1.0, 1.0, 0.0);
  box->SetTransform(flat);
  EXPECT_FALSE(box->GetZeroSetBounds(b));
}

TEST(SignedDistancePrimitives, BooleanTreesMatchCsgDistance)
{
  // VTK's boolean semantics (union min, intersection max, difference first
  // minus all others) over three of ours, against the core fold that the
  // solver builds for such trees. Values only: VTK 9.2's
  // vtkImplicitBoolean::EvaluateGradient returns minus the first function's
  // gradient whichever function decides the value (vtkSphere union shows
  // it), so the core's gradient, that of the deciding function, is the
  // right one to compare against the exact children below.
  vtkNew<vtkSignedDistanceSphere> a;
  a->SetCenter(-0.3, 0.0, 0.0);
  a->SetRadius(1.0);
  vtkNew<vtkSignedDistanceBox> b;
  b->SetCenter(0.4, 0.1, 0.0);
  b->SetHalfExtents(0.8, 0.6, 0.7);
  vtkNew<vtkSignedDistanceCapsule> c;
  c->SetPoint1(0.0, -1.0, 0.0);
  c->SetPoint2(0.0, 1.0, 0.5);
  c->SetRadius(0.3);
  using Shared = std::shared_ptr<const gridfree::SignedDistanceFunction<3>>;
  const Shared ca = std::make_shared<gridfree::SphereDistance<3>>(Vec3(-0.3, 0, 0), 1.0);
  const Shared cb =
    std::make_shared<gridfree::BoxDistance<3>>(Vec3(0.4, 0.1, 0), Vec3(0.8, 0.6, 0.7));
  const Shared cc =
    std::make_shared<gridfree::CapsuleDistance<3>>(Vec3(0, -1, 0), Vec3(0, 1, 0.5), 0.3);
  const std::pair<int, gridfree::CsgOperation> operations[] = {
    { vtkImplicitBoolean::VTK_UNION, gridfree::CsgOperation::Union },
    { vtkImplicitBoolean::VTK_INTERSECTION, gridfree::CsgOperation::Intersection },
    { vtkImplicitBoolean::VTK_DIFFERENCE, gridfree::CsgOperation::Difference }
  };
  for (const auto& [vtkOp, coreOp] : operations)
  {
    SCOPED_TRACE(vtkOp);
    vtkNew<vtkImplicitBoolean> tree;
    tree->SetOperationType(vtkOp);
    tree->AddFunction(a);
    tree->AddFunction(b);
    tree->AddFunction(c);
    const auto core = std::make_shared<gridfree::CsgDistance<3>>(
      coreOp, std::make_shared<gridfree::CsgDistance<3>>(coreOp, ca, cb), cc);
    ExpectSameAsCore(tree, *core, false);
    // The core's gradient is the deciding child's.
    for (const Vec3& p : TestPoints())
    {
      const double va = ca->Value(p), vb = cb->Value(p), vc = cc->Value(p);
      const double sign = coreOp == gridfree::CsgOperation::Difference ? -1.0 : 1.0;
      const double value = core->Value(p);
      Vec3 expected = ca->Gradient(p);
      if (value != va)
      {
        expected = sign * (value == sign * vb ? cb->Gradient(p) : cc->Gradient(p));
      }
      ASSERT_EQ(core->Gradient(p), expected) << "at " << p.transpose();
    }
  }
}

TEST(SignedDistancePrimitives, InvalidParametersGiveNaNAndASolverError)
{
  vtkNew<vtkSignedDistanceSphere> sphere;
  sphere->SetRadius(-1.0);
  vtkNew<vtkSignedDistanceBox> box;
  box->SetHalfExtents(1.0, 0.0, 1.0);
  vtkNew<vtkSignedDistanceRoundedBox> rounded;
  rounded->SetRounding(std::nan(""));
  vtkNew<vtkSignedDistanceTorus> torus;
  torus->SetMajorRadius(0.2);
  torus->SetMinorRadius(0.5); // a spindle torus has no exact distance
  vtkNew<vtkSignedDistanceCylinder> cylinder;
  cylinder->SetAxis(0.0, 0.0, 0.0);
  vtkNew<vtkSignedDistanceCapsule> capsule;
  capsule->SetRadius(0.0);
  vtkNew<vtkSignedDistancePlane> plane;
  plane->SetNormal(0.0, 0.0, 0.0);
  const std::vector<vtkSignedDistancePrimitive*> invalid = { sphere, box, rounded, torus,
    cylinder, capsule, plane };
  for (vtkSignedDistancePrimitive* f : invalid)
  {
    SCOPED_TRACE(f->GetClassName());
    EXPECT_FALSE(f->HasValidParameters());
    const std::string error = f->GetParameterError();
    EXPECT_NE(error.find(f->GetClassName()), std::string::npos) << error;
    double x[3] = { 0.1, 0.2, 0.3 }, g[3] = { 0, 0, 0 }, b[6];
    double value = 0.0;
    EXPECT_NO_THROW(value = f->FunctionValue(x));
    EXPECT_TRUE(std::isnan(value));
    EXPECT_NO_THROW(f->FunctionGradient(x, g));
    EXPECT_TRUE(std::isnan(g[0]) && std::isnan(g[1]) && std::isnan(g[2]));
    EXPECT_FALSE(f->GetZeroSetBounds(b));

    const std::string errors = SolverErrors(f);
    EXPECT_NE(errors.find("Cannot use the implicit boundary"), std::string::npos) << errors;
    EXPECT_NE(errors.find(f->GetClassName()), std::string::npos) << errors;
  }

  // Also when the bad primitive is deep in a tree with a VTK function.
  vtkNew<vtkSphere> vtkBall;
  vtkNew<vtkImplicitBoolean> inner, outer;
  inner->AddFunction(vtkBall);
  inner->AddFunction(torus);
  outer->SetOperationTypeToIntersection();
  outer->AddFunction(inner);
  const std::string errors = SolverErrors(outer);
  EXPECT_NE(errors.find("vtkSignedDistanceTorus"), std::string::npos) << errors;

  // Fixing the parameters makes it usable again.
  torus->SetMinorRadius(0.1);
  EXPECT_TRUE(torus->HasValidParameters());
  EXPECT_FALSE(std::isnan(torus->EvaluateFunction(0.0, 0.0, 0.0)));
}

TEST(SignedDistancePrimitives, SolverOnASphereMatchesClosedForm)
{
  // LipschitzBound left at 1: an exact distance needs no tuning and draws
  // no Lipschitz warning.
  vtkNew<vtkSignedDistanceSphere> sphere;
  sphere->SetCenter(0.2, -0.1, 0.3);
  sphere->SetRadius(1.1);
  ExpectSolverCalibrated(sphere, BallPoints(150, Vec3(0.2, -0.1, 0.3), 0.95));
}

TEST(SignedDistancePrimitives, SolverOnAUnionMatchesClosedForm)
{
  // A ball and a box overlapping: probe points in both lobes and the neck.
  vtkNew<vtkSignedDistanceSphere> ball;
  ball->SetCenter(-0.4, 0.0, 0.0);
  ball->SetRadius(0.6);
  vtkNew<vtkSignedDistanceBox> box;
  box->SetCenter(0.4, 0.0, 0.0);
  box->SetHalfExtents(0.5, 0.5, 0.5);
  vtkNew<vtkImplicitBoolean> both;
  both->SetOperationTypeToUnion();
  both->AddFunction(ball);
  both->AddFunction(box);
  auto probe = BallPoints(75, Vec3(-0.4, 0.0, 0.0), 0.5);
  Append(probe, BallPoints(75, Vec3(0.4, 0.0, 0.0), 0.45));
  // A LipschitzBound below 1 is not used for exact distances (no warning,
  // no overstepping walks).
  ExpectSolverCalibrated(both, probe, 0.3);
}

TEST(SignedDistancePrimitives, SolverOnADifferenceMatchesClosedForm)
{
  // A cube with a ball bitten out of one corner (VTK's difference: the
  // first function minus the others).
  vtkNew<vtkSignedDistanceBox> cube;
  cube->SetHalfExtents(0.8, 0.8, 0.8);
  vtkNew<vtkSignedDistanceSphere> bite;
  bite->SetCenter(0.8, 0.8, 0.8);
  bite->SetRadius(0.6);
  vtkNew<vtkImplicitBoolean> bitten;
  bitten->SetOperationTypeToDifference();
  bitten->AddFunction(cube);
  bitten->AddFunction(bite);
  auto probe = BallPoints(150, Vec3::Zero(), 0.75,
    [](const Vec3& p) { return (p - Vec3(0.8, 0.8, 0.8)).norm() > 0.65; });
  ExpectSolverCalibrated(bitten, probe);
}

TEST(SignedDistancePrimitives, SolverWithATransformedPrimitive)
{
  // Through VTK (a Transform is set): a rotated capsule, and a box scaled by
  // T x = 2 x, whose slope 2 the solver takes from the Transform itself, so
  // LipschitzBound = 1 neither oversteps nor warns.
  vtkNew<vtkSignedDistanceCapsule> capsule;
  capsule->SetPoint1(-0.5, 0.0, 0.0);
  capsule->SetPoint2(0.5, 0.0, 0.0);
  capsule->SetRadius(0.6);
  vtkNew<vtkTransform> rotation;
  rotation->RotateWXYZ(30.0, 1.0, 2.0, 3.0);
  capsule->SetTransform(rotation);
  ExpectSolverCalibrated(capsule, BallPoints(150, Vec3::Zero(), 0.55));

  vtkNew<vtkSignedDistanceBox> box;
  box->SetHalfExtents(1.0, 1.0, 1.0);
  vtkNew<vtkTransform> scale;
  scale->Scale(2.0, 2.0, 2.0);
  box->SetTransform(scale);
  ExpectSolverCalibrated(box, BallPoints(150, Vec3::Zero(), 0.45));
}
