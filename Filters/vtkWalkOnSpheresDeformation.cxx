#include "vtkWalkOnSpheresDeformation.h"

#include <gridfree/applications/DeformationBoundaryData.h>
#include <gridfree/implicit/MeshSignedDistance.h>
#include "GridFreeArrays.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataObjectTypes.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkStructuredGrid.h"
#include "vtkUnsignedCharArray.h"
#include "GridFreeArraySelection.h"
#include "GridFreeSolveSettings.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresDeformation);

namespace
{
const char* const kMap = "Deformation";
const char* const kMapLaplacian = "Deformation_Laplacian";

bool IsGrid(vtkDataObject* data)
{
  return vtkImageData::SafeDownCast(data) || vtkRectilinearGrid::SafeDownCast(data);
}

// Whether each probe point lies inside the Source curves, by the core's
// inside test of a closed mesh (MeshSignedDistance: ray parity with a
// majority vote, on its own hierarchy). The map is defined there only:
// walks from outside leave the curves' domain. `closed` is false when the
// curves do not close up (an end point met by an odd number of segments,
// points compared by their coordinates): there is no inside then, and every
// point counts as inside.
std::vector<char> InsideCurves(vtkPolyData* source, vtkDataSet* probe, bool& closed)
{
  std::vector<gridfree::Vec2> vertices;
  std::vector<gridfree::MeshSignedDistance<2>::Primitive> segments;
  std::map<std::pair<double, double>, int> ends;
  auto lines = vtk::TakeSmartPointer(source->GetLines()->NewIterator());
  for (lines->GoToFirstCell(); !lines->IsDoneWithTraversal(); lines->GoToNextCell())
  {
    vtkIdType count;
    const vtkIdType* ids;
    lines->GetCurrentCell(count, ids);
    for (vtkIdType k = 0; k + 1 < count; ++k)
    {
      double a[3], b[3];
      source->GetPoint(ids[k], a);
      source->GetPoint(ids[k + 1], b);
      if (a[0] == b[0] && a[1] == b[1])
      {
        continue;
      }
      const auto first = static_cast<std::int64_t>(vertices.size());
      vertices.emplace_back(a[0], a[1]);
      vertices.emplace_back(b[0], b[1]);
      segments.push_back({ first, first + 1 });
      ends[{ a[0], a[1] }] += 1;
      ends[{ b[0], b[1] }] += 1;
    }
  }
  closed = !segments.empty();
  for (const auto& end : ends)
  {
    closed = closed && end.second % 2 == 0;
  }
  const vtkIdType m = probe->GetNumberOfPoints();
  std::vector<char> inside(static_cast<std::size_t>(m), 1);
  if (!closed)
  {
    return inside;
  }
  // Ray tests are watertight for bit-identical coordinates, so the
  // duplicated end points need no welding.
  std::shared_ptr<const gridfree::MeshSignedDistance<2>> curves;
  try
  {
    curves = gridfree::MeshSignedDistance<2>::Create(std::move(vertices), std::move(segments));
  }
  catch (const std::exception&)
  {
    closed = false; // non-finite points: the solve says what is wrong
    return inside;
  }
  for (vtkIdType i = 0; i < m; ++i)
  {
    double p[3];
    probe->GetPoint(i, p);
    inside[static_cast<std::size_t>(i)] = curves->Inside(gridfree::Vec2(p[0], p[1])) ? 1 : 0;
  }
  return inside;
}
} // namespace

vtkWalkOnSpheresDeformation::vtkWalkOnSpheresDeformation()
{
  this->SetNumberOfInputPorts(3);
}

vtkWalkOnSpheresDeformation::~vtkWalkOnSpheresDeformation() = default;

void vtkWalkOnSpheresDeformation::SetTargetConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(TargetPort, output);
}

void vtkWalkOnSpheresDeformation::SetTargetData(vtkDataObject* data)
{
  this->SetInputData(TargetPort, data);
}

int vtkWalkOnSpheresDeformation::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  if (!probe)
  {
    return 1; // reported in RequestData
  }
  const std::string type = IsGrid(probe) ? "vtkStructuredGrid" : probe->GetClassName();
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject* output = outInfo->Get(vtkDataObject::DATA_OBJECT());
  if (!output || !output->IsA(type.c_str()))
  {
    vtkDataObject* fresh = vtkDataObjectTypes::NewDataObject(type.c_str());
    outInfo->Set(vtkDataObject::DATA_OBJECT(), fresh);
    fresh->FastDelete();
  }
  return 1;
}

int vtkWalkOnSpheresDeformation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  vtkPolyData* source = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkPointSet* target = vtkPointSet::GetData(inputVector[TargetPort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!probe || !output)
  {
    vtkErrorMacro(<< "No Probe: connect the 2D dataset to deform to port 1.");
    return 0;
  }
  if (!source || source->GetNumberOfLines() == 0 ||
    source->GetNumberOfPolys() + source->GetNumberOfStrips() > 0)
  {
    vtkErrorMacro(<< "The Source must be polylines in one z-plane (the 2D domain's boundary): "
                  << (source ? "it has no lines or has polygons." : "none is connected."));
    return 0;
  }
  if (!target || target->GetNumberOfPoints() != source->GetNumberOfPoints())
  {
    vtkErrorMacro(<< "The Target must have as many points as the Source ("
                  << source->GetNumberOfPoints() << "), point i being where source point i goes; "
                  << (target ? "it has " + std::to_string(target->GetNumberOfPoints()) + "."
                             : std::string("none is connected.")));
    return 0;
  }
  for (vtkIdType i = 0; i < target->GetNumberOfPoints(); ++i)
  {
    double p[3];
    target->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
    {
      vtkErrorMacro(<< "Target point " << i << " is not finite.");
      return 0;
    }
  }

  // The boundary data g (target position) and h (Laplacian) at the source
  // points, line by line.
  const vtkIdType n = source->GetNumberOfPoints();
  auto g = gridfree::MakeArray(kMap, 2, n);
  auto h = gridfree::MakeArray(kMapLaplacian, 2, n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    target->GetPoint(i, p);
    g->SetTuple2(i, p[0], p[1]);
    h->SetTuple2(i, 0.0, 0.0);
  }
  if (this->AsLinearAsPossible)
  {
    auto lines = vtk::TakeSmartPointer(source->GetLines()->NewIterator());
    for (lines->GoToFirstCell(); !lines->IsDoneWithTraversal(); lines->GoToNextCell())
    {
      vtkIdType count;
      const vtkIdType* ids;
      lines->GetCurrentCell(count, ids);
      std::vector<gridfree::Vec2> curve, image;
      for (vtkIdType k = 0; k < count; ++k)
      {
        double a[3], b[3];
        source->GetPoint(ids[k], a);
        target->GetPoint(ids[k], b);
        curve.emplace_back(a[0], a[1]);
        image.emplace_back(b[0], b[1]);
      }
      std::vector<gridfree::DeformationBoundarySample> data;
      try
      {
        data = gridfree::PolylineDeformationData(curve, image, count > 2 && ids[0] == ids[count - 1]);
      }
      catch (const std::exception& e)
      {
        vtkErrorMacro(<< "Cannot compute the boundary data: " << e.what() << ".");
        return 0;
      }
      for (vtkIdType k = 0; k < count && k < static_cast<vtkIdType>(data.size()); ++k)
      {
        h->SetTuple2(ids[k], data[k].Laplacian.x(), data[k].Laplacian.y());
      }
    }
  }
  vtkNew<vtkPolyData> boundary;
  boundary->SetPoints(source->GetPoints());
  boundary->SetLines(source->GetLines());
  boundary->GetPointData()->AddArray(g);
  boundary->GetPointData()->AddArray(h);

  const vtkIdType m = probe->GetNumberOfPoints();
  // Only the probe points inside the Source curves are solved for.
  bool closed = false;
  const std::vector<char> inside = InsideCurves(source, probe, closed);
  std::vector<vtkIdType> solvedAt(static_cast<std::size_t>(m), -1);
  vtkNew<vtkPoints> insidePoints;
  insidePoints->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < m; ++i)
  {
    if (inside[static_cast<std::size_t>(i)])
    {
      double x[3];
      probe->GetPoint(i, x);
      solvedAt[static_cast<std::size_t>(i)] = insidePoints->InsertNextPoint(x);
    }
  }
  const vtkIdType outside = m - insidePoints->GetNumberOfPoints();
  vtkNew<vtkPolyData> insideProbe;
  insideProbe->SetPoints(insidePoints);
  vtkSmartPointer<vtkDataSet> solved;
  if (insidePoints->GetNumberOfPoints() > 0)
  {
    // The properties this filter keeps (the sampling settings and its own),
    // the solver's defaults for the rest; the solve's own choices below.
    gridfree::SolveSettings settings = this->GetSettings();
    settings.Equation = gridfree::Equation::Biharmonic;
    gridfree::ArraySelections arrays;
    arrays.Select(0, vtkDataObject::FIELD_ASSOCIATION_POINTS, kMap);
    arrays.Select(1, vtkDataObject::FIELD_ASSOCIATION_POINTS, kMapLaplacian);
    bool aborted = false;
    if (!this->Solve(settings, arrays, boundary, nullptr, insideProbe, 0.0, 1.0, solved, aborted))
    {
      if (aborted)
      {
        vtkWarningMacro(<< "Deformation aborted: nothing is output.");
        return 1;
      }
      return 0;
    }
  }

  // The warped copy.
  vtkNew<vtkPoints> moved;
  moved->SetDataTypeToDouble();
  moved->SetNumberOfPoints(m);
  auto map = gridfree::MakeArray(kMap, 3, m);
  auto mapVariance = gridfree::MakeArray(std::string(kMap) + "_Variance", 3, m);
  auto displacement = gridfree::MakeArray("Displacement", 3, m);
  auto original = gridfree::MakeArray("SourcePosition", 3, m);
  vtkDataArray* value = solved ? solved->GetPointData()->GetArray(kMap) : nullptr;
  vtkDataArray* variance =
    solved ? solved->GetPointData()->GetArray((std::string(kMap) + "_Variance").c_str()) : nullptr;
  if (insidePoints->GetNumberOfPoints() > 0 && (!value || !variance))
  {
    vtkErrorMacro(<< "The internal solve did not give the map.");
    return 0;
  }
  vtkNew<vtkUnsignedCharArray> insideArray;
  insideArray->SetName("InsideSource");
  insideArray->SetNumberOfTuples(m);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (vtkIdType i = 0; i < m; ++i)
  {
    double x[3];
    probe->GetPoint(i, x);
    const vtkIdType j = solvedAt[static_cast<std::size_t>(i)];
    insideArray->SetValue(i, j >= 0 ? 1 : 0);
    if (j < 0)
    {
      // Outside the curves the map is not defined: the point stays.
      const double none[3] = { nan, nan, nan };
      const double still[3] = { 0.0, 0.0, 0.0 };
      moved->SetPoint(i, x);
      map->SetTuple(i, none);
      mapVariance->SetTuple(i, none);
      displacement->SetTuple(i, still);
      original->SetTuple(i, x);
      continue;
    }
    const double y[3] = { value->GetComponent(j, 0), value->GetComponent(j, 1), x[2] };
    const double v[3] = { variance->GetComponent(j, 0), variance->GetComponent(j, 1), 0.0 };
    const double d[3] = { y[0] - x[0], y[1] - x[1], 0.0 };
    moved->SetPoint(i, y);
    map->SetTuple(i, y);
    mapVariance->SetTuple(i, v);
    displacement->SetTuple(i, d);
    original->SetTuple(i, x);
  }
  if (outside > 0)
  {
    vtkWarningMacro(<< outside << " of " << m
                    << " probe points lie outside the Source curves, where the deformation is "
                       "not defined: they keep their place, with Deformation and "
                       "Deformation_Variance NaN there (array InsideSource is 0).");
  }
  if (auto* grid = vtkStructuredGrid::SafeDownCast(output); grid && IsGrid(probe))
  {
    int extent[6];
    if (auto* image = vtkImageData::SafeDownCast(probe))
    {
      image->GetExtent(extent);
    }
    else
    {
      vtkRectilinearGrid::SafeDownCast(probe)->GetExtent(extent);
    }
    grid->SetExtent(extent);
    grid->SetPoints(moved);
  }
  else if (auto* pointSet = vtkPointSet::SafeDownCast(output))
  {
    pointSet->CopyStructure(probe);
    pointSet->SetPoints(moved);
  }
  else
  {
    vtkErrorMacro(<< "Cannot warp a " << probe->GetClassName() << ".");
    return 0;
  }
  output->GetPointData()->PassData(probe->GetPointData());
  output->GetCellData()->PassData(probe->GetCellData());
  output->GetFieldData()->PassData(probe->GetFieldData());
  output->GetPointData()->AddArray(map);
  output->GetPointData()->AddArray(mapVariance);
  output->GetPointData()->AddArray(displacement);
  output->GetPointData()->AddArray(original);
  if (closed)
  {
    output->GetPointData()->AddArray(insideArray);
  }
  this->AddSummary(output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWalkOnSpheresDeformation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AsLinearAsPossible: " << this->AsLinearAsPossible << "\n";
}
