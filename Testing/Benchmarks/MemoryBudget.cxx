// Memory of a large solve through the filter: a 10,000,000-triangle soup as
// the Boundary (float points, three of their own per triangle, a float point
// array of values) and a 1,000,000-point image as the Probe, solved with the
// fewest walks the solver allows. Prints the resident memory of the inputs,
// the peak during vtkWalkOnSpheresSolver::Update() and what the solver holds
// per triangle and per probe point, against the budget stated in the
// documentation. Not a test: `./gridfree bench --memory` runs it.
#include "BenchmarkMeshes.h"
#include "vtkWalkOnSpheresSolver.h"

#include "vtkCellArray.h"
#include "vtkDataObject.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace
{
// Resident and peak resident memory (VmRSS, VmHWM) in MiB.
double StatusMiB(const char* key)
{
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(status, line))
  {
    if (line.compare(0, prefix.size(), prefix) == 0)
    {
      return std::atof(line.c_str() + prefix.size()) / 1024.0; // kB
    }
  }
  return -1.0;
}

// Resets the peak (VmHWM) to the current resident size, so the next peak is
// that of what follows; false where the kernel does not allow it.
bool ResetPeak()
{
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  return static_cast<bool>(clear);
}

// The soup as a vtkPolyData with a point array T = x + 2y (float), built
// without a second copy in double.
vtkSmartPointer<vtkPolyData> SoupPolyData(std::size_t triangles)
{
  gridfree::bench::TriangleMesh soup = gridfree::bench::MakeBumpySoup(triangles, 5);
  const vtkIdType numPoints = static_cast<vtkIdType>(soup.Vertices.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(numPoints);
  vtkNew<vtkFloatArray> values;
  values->SetName("T");
  values->SetNumberOfTuples(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    const auto& v = soup.Vertices[static_cast<std::size_t>(i)];
    points->SetPoint(i, v[0], v[1], v[2]);
    values->SetValue(i, static_cast<float>(v[0] + 2.0 * v[1]));
  }
  soup.Vertices = {};
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(soup.Simplices.size()) + 1);
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(soup.Simplices.size()) * 3);
  for (std::size_t t = 0; t < soup.Simplices.size(); ++t)
  {
    offsets->SetValue(static_cast<vtkIdType>(t), static_cast<vtkIdType>(3 * t));
    for (int k = 0; k < 3; ++k)
    {
      connectivity->SetValue(static_cast<vtkIdType>(3 * t + k), soup.Simplices[t][k]);
    }
  }
  offsets->SetValue(static_cast<vtkIdType>(soup.Simplices.size()),
    static_cast<vtkIdType>(3 * soup.Simplices.size()));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetPointData()->AddArray(values);
  return poly;
}
} // namespace

int main(int argc, char* argv[])
{
  std::size_t triangles = 10000000;
  int side = 100;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--quick")
    {
      triangles = 500000;
      side = 30;
    }
    else
    {
      std::fprintf(stderr, "Usage: %s [--quick]\n", argv[0]);
      return 2;
    }
  }
  vtkSmartPointer<vtkPolyData> boundary = SoupPolyData(triangles);
  double bounds[6];
  boundary->GetBounds(bounds);
  vtkNew<vtkImageData> probe;
  probe->SetDimensions(side, side, side);
  probe->SetOrigin(bounds[0], bounds[2], bounds[4]);
  probe->SetSpacing((bounds[1] - bounds[0]) / (side - 1), (bounds[3] - bounds[2]) / (side - 1),
    (bounds[5] - bounds[4]) / (side - 1));
  const double inputMiB =
    (boundary->GetActualMemorySize() + probe->GetActualMemorySize()) / 1024.0;
  const double rssBefore = StatusMiB("VmRSS");
  const bool peakReset = ResetPeak();

  vtkNew<vtkWalkOnSpheresSolver> solver;
  solver->SetInputData(0, boundary);
  solver->SetInputData(1, probe);
  solver->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
  solver->SetWalksPerPoint(2);
  solver->SetControlVariates(false);
  solver->SetEpsilon(1e-3);
  const auto start = std::chrono::steady_clock::now();
  solver->Update();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double peak = StatusMiB("VmHWM");
  const double outputMiB = solver->GetOutput()->GetActualMemorySize() / 1024.0;

  const double numTriangles = static_cast<double>(boundary->GetNumberOfCells());
  const double numProbe = static_cast<double>(probe->GetNumberOfPoints());
  const double solverMiB = peak - rssBefore;
  std::printf("# Memory of a solve\n\n");
  std::printf("%.0f boundary triangles (a soup: %lld float points, a float value array), "
              "%.0f probe points (an image), 2 walks per point, epsilon 1e-3 of the diagonal, "
              "%.1f s.\n\n",
    numTriangles, static_cast<long long>(boundary->GetNumberOfPoints()), numProbe, seconds);
  std::printf("| what | MiB |\n|---|---:|\n");
  std::printf("| inputs (VTK's GetActualMemorySize) | %.0f |\n", inputMiB);
  std::printf("| resident before Update | %.0f |\n", rssBefore);
  std::printf("| peak resident during Update%s | %.0f |\n",
    peakReset ? "" : " (process peak: clear_refs not allowed)", peak);
  std::printf("| solver's own peak (peak minus resident before) | %.0f |\n", solverMiB);
  std::printf("| output arrays (of it) | %.0f |\n", outputMiB);
  std::printf("\nSolver's peak: %.0f bytes per boundary triangle, with the output's %.0f bytes "
              "per probe point counted apart.\n",
    (solverMiB - outputMiB) * 1048576.0 / numTriangles, outputMiB * 1048576.0 / numProbe);
  const double walks = solver->GetLastNumberOfWalks();
  std::printf("Walks: %.0f (%.0f per second).\n", walks, walks / seconds);
  return 0;
}
