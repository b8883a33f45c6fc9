#include "vtkWalkOnSpheresDeformation.h"

#include <gridfree/applications/DeformationBoundaryData.h>
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
#include "GridFreeArraySelection.h"
#include "GridFreeSolveSettings.h"
#include "vtkWalkOnSpheresSolver.h" // for its enumerations

#include <cmath>
#include <stdexcept>
#include <string>
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
  vtkSmartPointer<vtkDataSet> solved;
  if (m > 0)
  {
    gridfree::SolveSettings settings = this->SamplingSettings();
    settings.Equation = vtkWalkOnSpheresSolver::BIHARMONIC;
    gridfree::ArraySelections arrays;
    arrays.Select(0, vtkDataObject::FIELD_ASSOCIATION_POINTS, kMap);
    arrays.Select(1, vtkDataObject::FIELD_ASSOCIATION_POINTS, kMapLaplacian);
    bool aborted = false;
    if (!this->Solve(settings, arrays, boundary, nullptr, probe, 0.0, 1.0, solved, aborted))
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
  if (m > 0 && (!value || !variance))
  {
    vtkErrorMacro(<< "The internal solve did not give the map.");
    return 0;
  }
  for (vtkIdType i = 0; i < m; ++i)
  {
    double x[3];
    probe->GetPoint(i, x);
    const double y[3] = { value->GetComponent(i, 0), value->GetComponent(i, 1), x[2] };
    const double v[3] = { variance->GetComponent(i, 0), variance->GetComponent(i, 1), 0.0 };
    const double d[3] = { y[0] - x[0], y[1] - x[1], 0.0 };
    moved->SetPoint(i, y);
    map->SetTuple(i, y);
    mapVariance->SetTuple(i, v);
    displacement->SetTuple(i, d);
    original->SetTuple(i, x);
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
  this->AddSummary(output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWalkOnSpheresDeformation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AsLinearAsPossible: " << this->AsLinearAsPossible << "\n";
}
