#include "vtkBoundaryConditionMarker.h"

#include "vtkCell.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkBoundaryConditionMarker);
vtkCxxSetObjectMacro(vtkBoundaryConditionMarker, Region, vtkImplicitFunction);

vtkBoundaryConditionMarker::~vtkBoundaryConditionMarker()
{
  this->SetRegion(nullptr);
}

vtkMTimeType vtkBoundaryConditionMarker::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->Region)
  {
    time = std::max(time, this->Region->GetMTime());
  }
  return time;
}

namespace
{
// A one-component cell array named `name` with the input's values where it
// has such an array, else `fill`.
template <class Array>
vtkSmartPointer<Array> StartFrom(vtkCellData* input, const char* name, vtkIdType cells, double fill)
{
  auto out = vtkSmartPointer<Array>::New();
  out->SetName(name);
  out->SetNumberOfTuples(cells);
  vtkDataArray* given = input->GetArray(name);
  const bool usable = given && given->GetNumberOfComponents() == 1 &&
    given->GetNumberOfTuples() == cells;
  for (vtkIdType c = 0; c < cells; ++c)
  {
    out->SetTuple1(c, usable ? given->GetTuple1(c) : fill);
  }
  return out;
}
}

int vtkBoundaryConditionMarker::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro(<< "The input must be a surface (vtkPolyData).");
    return 0;
  }
  if (!this->Region)
  {
    vtkErrorMacro(<< "No Region is set: give an implicit function (a plane, box, sphere or "
                     "cylinder) whose inside is the part to mark.");
    return 0;
  }
  output->ShallowCopy(input);
  const vtkIdType cells = input->GetNumberOfCells();
  if (cells == 0)
  {
    vtkWarningMacro(<< "The input has no cells: nothing to mark.");
  }
  vtkCellData* given = input->GetCellData();
  auto bc = StartFrom<vtkIntArray>(given, "bc", cells, 0.0);
  auto mu = StartFrom<vtkDoubleArray>(given, "mu", cells, 0.0);
  auto h = StartFrom<vtkDoubleArray>(given, "h", cells, 0.0);
  vtkNew<vtkIdList> ids;
  vtkIdType marked = 0;
  for (vtkIdType c = 0; c < cells; ++c)
  {
    if (c % 4096 == 0)
    {
      this->UpdateProgress(static_cast<double>(c) / static_cast<double>(cells));
      if (this->CheckAbort())
      {
        break;
      }
    }
    input->GetCellPoints(c, ids);
    const vtkIdType n = ids->GetNumberOfIds();
    if (n == 0)
    {
      continue;
    }
    double centre[3] = { 0.0, 0.0, 0.0 };
    for (vtkIdType k = 0; k < n; ++k)
    {
      double p[3];
      input->GetPoint(ids->GetId(k), p);
      for (int d = 0; d < 3; ++d)
      {
        centre[d] += p[d] / static_cast<double>(n);
      }
    }
    const double value = this->Region->FunctionValue(centre);
    if (!(this->InsideOut ? value > 0.0 : value < 0.0))
    {
      continue;
    }
    ++marked;
    bc->SetValue(c, this->Condition);
    mu->SetValue(c, this->Condition == ROBIN ? this->RobinCoefficient : 0.0);
    h->SetValue(c, this->Condition == NEUMANN || this->Condition == ROBIN ? this->Flux : 0.0);
  }
  output->GetCellData()->AddArray(bc);
  output->GetCellData()->AddArray(mu);
  output->GetCellData()->AddArray(h);
  auto count = vtkSmartPointer<vtkIntArray>::New();
  count->SetName("MarkedCells");
  count->InsertNextValue(static_cast<int>(marked));
  output->GetFieldData()->AddArray(count);
  return 1;
}

void vtkBoundaryConditionMarker::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Condition: " << this->Condition << "\n";
  os << indent << "Region: " << this->Region << "\n";
  os << indent << "InsideOut: " << (this->InsideOut ? "On" : "Off") << "\n";
  os << indent << "RobinCoefficient: " << this->RobinCoefficient << "\n";
  os << indent << "Flux: " << this->Flux << "\n";
}
