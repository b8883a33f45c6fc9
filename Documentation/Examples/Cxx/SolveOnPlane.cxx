// Using GridFree from C++: solve a Laplace problem inside a sphere whose
// surface carries T = x^2 - y^2, on a plane through it, and print a few values
// beside the exact solution (x^2 - y^2 is harmonic, so it is its own solution).
#include "vtkWalkOnSpheresSolver.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <cmath>
#include <cstdio>

int main()
{
  // The boundary: a triangulated unit sphere with a point array "T".
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(96);
  sphere->SetPhiResolution(96);
  sphere->Update();
  vtkNew<vtkPolyData> boundary;
  boundary->DeepCopy(sphere->GetOutput());
  vtkNew<vtkDoubleArray> t;
  t->SetName("T");
  for (vtkIdType i = 0; i < boundary->GetNumberOfPoints(); ++i)
  {
    double p[3];
    boundary->GetPoint(i, p);
    t->InsertNextValue(p[0] * p[0] - p[1] * p[1]);
  }
  boundary->GetPointData()->AddArray(t);

  // The probe: any vtkDataSet; here a 5 x 5 plane through the sphere.
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-0.5, -0.5, 0.0);
  plane->SetPoint1(0.5, -0.5, 0.0);
  plane->SetPoint2(-0.5, 0.5, 0.0);
  plane->SetResolution(4, 4);

  vtkNew<vtkWalkOnSpheresSolver> solver;
  solver->SetBoundaryData(boundary);
  solver->SetProbeConnection(plane->GetOutputPort());
  solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
  solver->SetWalksPerPoint(1024);
  solver->Update();

  vtkPolyData* out = vtkPolyData::SafeDownCast(solver->GetOutput());
  vtkDataArray* u = out->GetPointData()->GetArray("T");
  vtkDataArray* var = out->GetPointData()->GetArray("T_Variance");
  int outliers = 0;
  std::printf("%8s %8s %10s %10s %10s\n", "x", "y", "estimate", "exact", "std.err.");
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    const double exact = p[0] * p[0] - p[1] * p[1];
    const double stderror = std::sqrt(var->GetTuple1(i));
    std::printf("%8.3f %8.3f %10.4f %10.4f %10.4f\n", p[0], p[1], u->GetTuple1(i), exact, stderror);
    outliers += std::abs(u->GetTuple1(i) - exact) > 5.0 * stderror + 1e-3 ? 1 : 0;
  }
  std::printf("%lld walks in %.2f s (%.0f walks/s)\n",
    static_cast<long long>(solver->GetLastNumberOfWalks()), solver->GetLastSolveSeconds(),
    solver->GetLastWalksPerSecond());
  return outliers == 0 ? 0 : 1;
}
