// vtkWalkOnSpheresSolver through its C++ API: output type and arrays, the
// accuracy of a solve in a VTK pipeline, thread-count invariance and the
// errors reported for bad input.
#include "vtkWalkOnSpheresSolver.h"

#include "VtkMessageCatcher.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkExecutive.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
// A fine sphere of radius 1 carrying g = x^2 - y^2 (harmonic) as "T".
vtkSmartPointer<vtkPolyData> MakeSphereBoundary()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(128);
  sphere->SetPhiResolution(128);
  sphere->Update();
  auto boundary = vtkSmartPointer<vtkPolyData>::New();
  boundary->DeepCopy(sphere->GetOutput());
  vtkNew<vtkDoubleArray> t;
  t->SetName("T");
  t->SetNumberOfTuples(boundary->GetNumberOfPoints());
  for (vtkIdType i = 0; i < boundary->GetNumberOfPoints(); ++i)
  {
    double p[3];
    boundary->GetPoint(i, p);
    t->SetValue(i, p[0] * p[0] - p[1] * p[1]);
  }
  boundary->GetPointData()->AddArray(t);
  return boundary;
}

vtkSmartPointer<vtkImageData> MakeImageProbe()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(9, 9, 3);
  image->SetOrigin(-0.5, -0.5, -0.1);
  image->SetSpacing(0.125, 0.125, 0.1);
  return image;
}
} // namespace

TEST(WalkOnSpheresSolverFilter, ImageProbeStaysImageWithAllArrays)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  solver->SetBoundaryData(MakeSphereBoundary());
  solver->SetProbeData(MakeImageProbe());
  solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
  solver->SetWalksPerPoint(256);
  solver->Update();
  vtkImageData* out = vtkImageData::SafeDownCast(solver->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr);
  int dims[3];
  out->GetDimensions(dims);
  EXPECT_EQ(dims[0], 9);
  EXPECT_EQ(dims[2], 3);
  vtkPointData* pd = out->GetPointData();
  for (const char* name : { "T", "T_Variance", "WalkSteps", "EscapedFraction", "TruncatedFraction" })
  {
    ASSERT_NE(pd->GetArray(name), nullptr) << name;
  }
  EXPECT_STREQ(pd->GetScalars()->GetName(), "T");
  EXPECT_EQ(solver->GetLastDimension(), 3);
  EXPECT_EQ(solver->GetLastNumberOfWalks(), 256 * out->GetNumberOfPoints());
  EXPECT_NE(out->GetFieldData()->GetArray("TotalWalks"), nullptr);

  // Accuracy: |z| < 5 at every point (the sphere mesh is fine enough that its
  // discretization error is far below the standard error).
  vtkDataArray* t = pd->GetArray("T");
  vtkDataArray* var = pd->GetArray("T_Variance");
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    const double exact = p[0] * p[0] - p[1] * p[1];
    EXPECT_LT(std::abs(t->GetTuple1(i) - exact), 5.0 * std::sqrt(var->GetTuple1(i)) + 2e-3);
    EXPECT_EQ(pd->GetArray("EscapedFraction")->GetTuple1(i), 0.0);
  }
}

TEST(WalkOnSpheresSolverFilter, SameOutputForOneAndTwoThreads)
{
  auto boundary = MakeSphereBoundary();
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-0.7, -0.7, 0.1);
  plane->SetPoint1(0.7, -0.7, 0.1);
  plane->SetPoint2(-0.7, 0.7, 0.1);
  plane->SetResolution(20, 20);
  auto run = [&](int threads) {
    vtkNew<vtkWalkOnSpheresSolver> solver;
    solver->SetBoundaryData(boundary);
    solver->SetProbeConnection(plane->GetOutputPort());
    solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    solver->SetWalksPerPoint(16);
    solver->SetSeed(7);
    solver->SetNumberOfThreads(threads);
    solver->Update();
    auto copy = vtkSmartPointer<vtkDoubleArray>::New();
    copy->DeepCopy(vtkPolyData::SafeDownCast(solver->GetOutput())->GetPointData()->GetArray("T"));
    return copy;
  };
  auto one = run(1);
  auto two = run(2);
  ASSERT_EQ(one->GetNumberOfTuples(), 441);
  for (vtkIdType i = 0; i < one->GetNumberOfTuples(); ++i)
  {
    ASSERT_EQ(one->GetValue(i), two->GetValue(i));
  }
}

// A probe of three points on two threads spreads each point's walks over the
// threads (walk-level parallelism); the numbers must still be bit for bit
// those of one thread, which solves the points one after the other. The
// walk count is not a multiple of the block sizes, so the last block is
// short. Both estimators: the derivative one (control variates, the
// default, with the gradient) and the plain one.
TEST(WalkOnSpheresSolverFilter, FewPointsSpreadWalksOverThreadsWithSameOutput)
{
  for (bool derivatives : { true, false })
  {
    auto boundary = MakeSphereBoundary();
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(0.1, 0.2, -0.3);
    points->InsertNextPoint(-0.5, 0.1, 0.2);
    points->InsertNextPoint(0.0, 0.0, 0.95);
    vtkNew<vtkPolyData> probe;
    probe->SetPoints(points);
    auto run = [&](int threads) {
      vtkNew<vtkWalkOnSpheresSolver> solver;
      solver->SetBoundaryData(boundary);
      solver->SetProbeData(probe);
      solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
      solver->SetWalksPerPoint(1000);
      solver->SetSeed(3);
      solver->SetNumberOfThreads(threads);
      solver->SetControlVariates(derivatives);
      solver->SetComputeGradient(derivatives);
      solver->Update();
      EXPECT_EQ(solver->GetLastNumberOfWalks(), 3000);
      auto copy = vtkSmartPointer<vtkPolyData>::New();
      copy->DeepCopy(vtkPolyData::SafeDownCast(solver->GetOutput()));
      return copy;
    };
    auto one = run(1);
    auto two = run(2);
    for (const char* name : { "T", "T_Variance", "WalkSteps", "T_Gradient" })
    {
      vtkDataArray* a = one->GetPointData()->GetArray(name);
      vtkDataArray* b = two->GetPointData()->GetArray(name);
      if (!derivatives && std::string(name) == "T_Gradient")
      {
        EXPECT_EQ(a, nullptr);
        continue;
      }
      ASSERT_NE(a, nullptr) << name;
      ASSERT_NE(b, nullptr) << name;
      for (vtkIdType i = 0; i < 3; ++i)
      {
        for (int c = 0; c < a->GetNumberOfComponents(); ++c)
        {
          EXPECT_TRUE(std::isfinite(a->GetComponent(i, c))) << name << " " << i;
          EXPECT_EQ(a->GetComponent(i, c), b->GetComponent(i, c)) << name << " " << i;
        }
      }
    }
  }
}

TEST(WalkOnSpheresSolverFilter, BadInputIsAnErrorNotACrash)
{
  auto expectError = [](vtkPolyData* boundary, const char* array, const char* fragment) {
    vtkNew<vtkWalkOnSpheresSolver> solver;
    vtkNew<MessageCatcher> catcher;
    solver->AddObserver(vtkCommand::ErrorEvent, catcher);
    solver->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
    solver->SetBoundaryData(boundary);
    solver->SetProbeData(MakeImageProbe());
    if (array)
    {
      solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, array);
    }
    solver->Update();
    EXPECT_NE(catcher->Errors.find(fragment), std::string::npos)
      << "expected '" << fragment << "' in: " << catcher->Errors;
  };
  vtkNew<vtkPolyData> empty;
  expectError(empty, "T", "empty");
  expectError(MakeSphereBoundary(), "Missing", "no point or cell array named 'Missing'");
  auto nan = MakeSphereBoundary();
  vtkDoubleArray::SafeDownCast(nan->GetPointData()->GetArray("T"))->SetValue(3, std::nan(""));
  expectError(nan, "T", "NaN");
  auto noScalars = MakeSphereBoundary();
  expectError(noScalars, nullptr, "No boundary values");
  // A cell that refers to a point the boundary does not have (a corrupt
  // file): an error naming the cell, never a read beyond the points.
  auto missing = MakeSphereBoundary();
  const vtkIdType cell[3] = { 0, 1, missing->GetNumberOfPoints() + 7 };
  missing->GetPolys()->InsertNextCell(3, cell);
  expectError(missing, "T", "refers to point");
}

// Gradient and Hessian of g = x² − y² (∇u = (2x, −2y, 0), ∇²u = diag(2, −2, 0))
// through the filter: named arrays, active vectors and tensors, accuracy
// within 5 standard errors, and the same numbers on 1 and 2 threads.
TEST(WalkOnSpheresSolverFilter, GradientAndHessianArrays)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  solver->SetBoundaryData(MakeSphereBoundary());
  solver->SetProbeData(MakeImageProbe());
  solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
  solver->SetWalksPerPoint(256);
  solver->ComputeGradientOn();
  solver->ComputeHessianOn();
  solver->ComputeDirectionalDerivativeOn();
  solver->SetDerivativeDirection(0.0, 1.0, 0.0);
  solver->SetNumberOfThreads(2);
  solver->Update();
  vtkDataSet* out = vtkDataSet::SafeDownCast(solver->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr);
  vtkPointData* pd = out->GetPointData();
  vtkDataArray* gradient = pd->GetArray("T_Gradient");
  vtkDataArray* gradientVariance = pd->GetArray("T_Gradient_Variance");
  vtkDataArray* hessian = pd->GetArray("T_Hessian");
  vtkDataArray* hessianVariance = pd->GetArray("T_Hessian_Variance");
  vtkDataArray* directional = pd->GetArray("T_DirectionalDerivative");
  vtkDataArray* status = pd->GetArray("DerivativeStatus");
  ASSERT_NE(gradient, nullptr);
  ASSERT_NE(gradientVariance, nullptr);
  ASSERT_NE(hessian, nullptr);
  ASSERT_NE(hessianVariance, nullptr);
  ASSERT_NE(directional, nullptr);
  ASSERT_NE(status, nullptr);
  EXPECT_EQ(gradient->GetNumberOfComponents(), 3);
  EXPECT_EQ(hessian->GetNumberOfComponents(), 9);
  EXPECT_EQ(pd->GetVectors(), gradient);
  EXPECT_EQ(pd->GetTensors(), hessian);
  EXPECT_EQ(pd->GetScalars(), pd->GetArray("T"));
  double worst = 0.0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    EXPECT_EQ(status->GetTuple1(i), 0.0);
    const double g[3] = { 2.0 * p[0], -2.0 * p[1], 0.0 };
    const double h[9] = { 2, 0, 0, 0, -2, 0, 0, 0, 0 };
    for (int k = 0; k < 3; ++k)
    {
      const double z = (gradient->GetComponent(i, k) - g[k]) /
        std::sqrt(gradientVariance->GetComponent(i, k));
      worst = std::max(worst, std::abs(z));
    }
    for (int k = 0; k < 9; ++k)
    {
      const double z = (hessian->GetComponent(i, k) - h[k]) /
        std::sqrt(hessianVariance->GetComponent(i, k));
      worst = std::max(worst, std::abs(z));
      EXPECT_EQ(hessian->GetComponent(i, k), hessian->GetComponent(i, 3 * (k % 3) + k / 3));
    }
    EXPECT_DOUBLE_EQ(directional->GetTuple1(i), gradient->GetComponent(i, 1));
  }
  EXPECT_LT(worst, 5.0);

  vtkNew<vtkDoubleArray> first;
  first->DeepCopy(hessian);
  solver->SetNumberOfThreads(1);
  solver->Update();
  vtkDataArray* again = vtkDataSet::SafeDownCast(solver->GetOutputDataObject(0))
                          ->GetPointData()
                          ->GetArray("T_Hessian");
  for (vtkIdType i = 0; i < first->GetNumberOfValues(); ++i)
  {
    ASSERT_EQ(first->GetValue(i), again->GetComponent(i / 9, i % 9));
  }
}

// A 2D problem (a circle of line segments) pads its derivatives with zero z
// components; a 3-component boundary array gets divergence and curl.
TEST(WalkOnSpheresSolverFilter, TwoDimensionalVectorSolutionHasDivergenceAndCurl)
{
  const int n = 2048;
  vtkNew<vtkPolyData> circle;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkDoubleArray> v;
  v->SetName("V");
  v->SetNumberOfComponents(3);
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * M_PI * i / n;
    const double x = std::cos(a), y = std::sin(a);
    points->InsertNextPoint(x, y, 0.0);
    // V = (x, −y, xy): ∇·V = 0 (in the plane), ∇×V = (x, −y, 0).
    v->InsertNextTuple3(x, -y, x * y);
  }
  for (int i = 0; i < n; ++i)
  {
    const vtkIdType ids[2] = { i, (i + 1) % n };
    lines->InsertNextCell(2, ids);
  }
  circle->SetPoints(points);
  circle->SetLines(lines);
  circle->GetPointData()->AddArray(v);
  vtkNew<vtkPolyData> probe;
  vtkNew<vtkPoints> probePoints;
  probePoints->InsertNextPoint(0.2, 0.3, 0.0);
  probePoints->InsertNextPoint(-0.4, 0.1, 0.0);
  probePoints->InsertNextPoint(1.0, 0.0, 0.0); // on the boundary: one-sided
  probe->SetPoints(probePoints);

  vtkNew<vtkWalkOnSpheresSolver> solver;
  solver->SetBoundaryData(circle);
  solver->SetProbeData(probe);
  solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "V");
  solver->SetWalksPerPoint(1024);
  solver->ComputeGradientOn();
  solver->Update();
  vtkPointData* pd = vtkDataSet::SafeDownCast(solver->GetOutputDataObject(0))->GetPointData();
  vtkDataArray* gradient = pd->GetArray("V_Gradient");
  vtkDataArray* divergence = pd->GetArray("V_Divergence");
  vtkDataArray* divergenceVariance = pd->GetArray("V_Divergence_Variance");
  vtkDataArray* curl = pd->GetArray("V_Curl");
  vtkDataArray* curlVariance = pd->GetArray("V_Curl_Variance");
  vtkDataArray* status = pd->GetArray("DerivativeStatus");
  ASSERT_NE(gradient, nullptr);
  ASSERT_NE(divergence, nullptr);
  ASSERT_NE(curl, nullptr);
  ASSERT_NE(status, nullptr);
  EXPECT_EQ(gradient->GetNumberOfComponents(), 9);
  EXPECT_EQ(pd->GetVectors(), nullptr); // a Jacobian is not a vector field
  for (vtkIdType i = 0; i < 2; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_EQ(gradient->GetComponent(i, 3 * c + 2), 0.0); // ∂/∂z in 2D
    }
    double p[3];
    probePoints->GetPoint(i, p);
    EXPECT_LT(std::abs(divergence->GetTuple1(i)), 5.0 * std::sqrt(divergenceVariance->GetTuple1(i)));
    const double exact[3] = { p[0], -p[1], 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_LT(std::abs(curl->GetComponent(i, k) - exact[k]),
        5.0 * std::sqrt(curlVariance->GetComponent(i, k)) + 1e-12);
    }
    EXPECT_EQ(status->GetTuple1(i), 0.0);
  }
  EXPECT_EQ(status->GetTuple1(2), 1.0);
  for (int k = 0; k < gradient->GetNumberOfComponents(); ++k)
  {
    EXPECT_TRUE(std::isfinite(gradient->GetComponent(2, k)));
  }
}
