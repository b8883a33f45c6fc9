// Nothing allocates per walk in the VTK adapters either: volume sources from
// an expression, an image and any other dataset (through vtkStaticCellLocator
// and a per-thread vtkGenericCell), boundary values from an expression, and
// implicit boundaries evaluated through VTK (see AllocationCounter.h).
#include "AllocationCounter.h"
#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include "GridFreeImplicitBoundary.h"
#include "GridFreeSourceConversion.h"
#include <gridfree/estimators/WalkOnSpheres.h>

#include "vtkBox.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkImplicitBoolean.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSphere.h"
#include "vtkStructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
Boundary<3> SphereBoundary()
{
  return MakeBoundary<3>(UnitSphereMesh<3>(), { [](const Vec3& x) { return x[0]; } });
}

WalkSettings PoissonSettings()
{
  WalkSettings s;
  s.Epsilon = 1e-3;
  s.Problem = Equation::Poisson;
  return s;
}

// Point array f = 1 + x y on the dataset's points.
void AddSourceArray(vtkDataSet* data)
{
  vtkNew<vtkDoubleArray> f;
  f->SetName("f");
  f->SetNumberOfTuples(data->GetNumberOfPoints());
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    double p[3];
    data->GetPoint(i, p);
    f->SetValue(i, 1.0 + p[0] * p[1]);
  }
  data->GetPointData()->AddArray(f);
}

// Plain and derivative (gradient: the sources' EvaluateGradient) walks with
// the volume source described by `source`, `array` and `expression`.
void CheckSource(vtkDataSet* source, vtkDataArray* array, const std::string& expression)
{
  SourceSet<3> description;
  std::string reason;
  ASSERT_TRUE(ConvertSource<3>(source, array, expression, 1, 0.0, description, reason)) << reason;
  ASSERT_TRUE(description.MakeVolume);
  const Boundary<3> boundary = SphereBoundary();
  auto volume = description.MakeVolume(boundary.Diagonal());
  WalkOnSpheresEstimator<3> plain(boundary, PoissonSettings(), volume.get());
  EXPECT_EQ(AllocationsOfWalks<3>(plain, 1), 0);
  DerivativeRequest request;
  request.Gradient = true;
  DerivativeWalkOnSpheres<3> derivative(boundary, PoissonSettings(), request, volume.get());
  EXPECT_EQ(AllocationsOfWalks<3>(derivative, derivative.Layout().Size), 0);
}

// A box of (n+1)³ points over [-1.2, 1.2]³.
constexpr int GridCells = 12;
constexpr double GridHalf = 1.2;
} // namespace

TEST(NoAllocationInAdapters, ExpressionSource)
{
  CheckSource(nullptr, nullptr, "1 + x*y + sin(z)");
}

TEST(NoAllocationInAdapters, ImageSource)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(GridCells + 1, GridCells + 1, GridCells + 1);
  image->SetOrigin(-GridHalf, -GridHalf, -GridHalf);
  const double h = 2.0 * GridHalf / GridCells;
  image->SetSpacing(h, h, h);
  AddSourceArray(image);
  CheckSource(image, image->GetPointData()->GetArray("f"), "");
}

TEST(NoAllocationInAdapters, StructuredGridSourceThroughTheCellLocator)
{
  vtkNew<vtkStructuredGrid> grid;
  grid->SetDimensions(GridCells + 1, GridCells + 1, GridCells + 1);
  vtkNew<vtkPoints> points;
  const double h = 2.0 * GridHalf / GridCells;
  for (int k = 0; k <= GridCells; ++k)
  {
    for (int j = 0; j <= GridCells; ++j)
    {
      for (int i = 0; i <= GridCells; ++i)
      {
        points->InsertNextPoint(-GridHalf + i * h, -GridHalf + j * h, -GridHalf + k * h);
      }
    }
  }
  grid->SetPoints(points);
  AddSourceArray(grid);
  CheckSource(grid, grid->GetPointData()->GetArray("f"), "");
}

// An implicit boundary called through VTK (a vtkImplicitBoolean of a sphere
// and a box, which the core cannot run itself) with boundary values from an
// expression.
TEST(NoAllocationInAdapters, VtkImplicitFunctionWithExpressionValues)
{
  vtkNew<vtkSphere> sphere;
  sphere->SetRadius(1.0);
  vtkNew<vtkBox> box;
  box->SetBounds(0.7, 1.5, -0.2, 0.2, -0.2, 0.2);
  vtkNew<vtkImplicitBoolean> difference;
  difference->SetOperationTypeToDifference();
  difference->AddFunction(sphere);
  difference->AddFunction(box);
  auto phi = std::make_shared<VtkImplicitFunctionDistance>(difference, 2.0);
  const auto values = std::make_shared<VolumeBoundaryValues<3>>(
    MakeExpressionListFactory<3>({ "x*y - z" }, 0.0), 1);
  Boundary<3> boundary;
  boundary.SetGeometry(std::make_shared<ImplicitBoundaryGeometry<3>>(phi, 2.0), values);
  WalkSettings s;
  s.Epsilon = 1e-3;
  WalkOnSpheresEstimator<3> estimator(boundary, s);
  EXPECT_EQ(AllocationsOfWalks<3>(estimator, 1), 0);
}
