// vtkWalkOnSpheresSolver through its C++ API: output type and arrays, the
// accuracy of a solve in a VTK pipeline, thread-count invariance and the
// errors reported for bad input.
#include "vtkWalkOnSpheresSolver.h"

#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkExecutive.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
// Records errors and warnings instead of printing them.
class MessageCatcher : public vtkCommand
{
public:
  static MessageCatcher* New() { return new MessageCatcher; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? Errors : Warnings) += text;
  }
  std::string Errors, Warnings;
};

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
}
