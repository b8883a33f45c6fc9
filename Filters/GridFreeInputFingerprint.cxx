#include "GridFreeInputFingerprint.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkPointData.h"
#include "vtkCellData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cstring>

namespace gridfree
{
// What a dataset's content is made of: its arrays (points, cells, point,
// cell and field data) by identity and modification time, and the values
// that define an image's or a rectilinear grid's geometry. Pipelines often
// hand a filter a fresh shallow copy of the same data (ParaView's
// vtkPVPostFilter does, at every update), whose own MTime moves while its
// arrays stay the same; any real edit changes an array or these values.
void AppendFingerprint(vtkObject* object, std::vector<std::uint64_t>& print)
{
  auto add = [&print](const void* p, vtkMTimeType t) {
    print.push_back(static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p)));
    print.push_back(static_cast<std::uint64_t>(t));
  };
  auto addDouble = [&print](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    print.push_back(bits);
  };
  auto addAttributes = [&add](vtkFieldData* fd) {
    if (!fd)
    {
      return;
    }
    for (int k = 0; k < fd->GetNumberOfArrays(); ++k)
    {
      vtkAbstractArray* a = fd->GetAbstractArray(k);
      add(a, a ? a->GetMTime() : 0);
    }
  };
  if (!object)
  {
    add(nullptr, 0);
    return;
  }
  auto* data = vtkDataObject::SafeDownCast(object);
  if (!data)
  {
    add(object, object->GetMTime()); // the implicit function
    return;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    auto it = vtk::TakeSmartPointer(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      AppendFingerprint(it->GetCurrentDataObject(), print);
    }
    return;
  }
  addAttributes(data->GetFieldData());
  auto* dataset = vtkDataSet::SafeDownCast(data);
  if (!dataset)
  {
    add(data, data->GetMTime());
    return;
  }
  print.push_back(static_cast<std::uint64_t>(dataset->GetNumberOfPoints()));
  print.push_back(static_cast<std::uint64_t>(dataset->GetNumberOfCells()));
  addAttributes(dataset->GetPointData());
  addAttributes(dataset->GetCellData());
  if (auto* pointSet = vtkPointSet::SafeDownCast(dataset))
  {
    vtkPoints* points = pointSet->GetPoints();
    add(points, points ? points->GetMTime() : 0);
  }
  if (auto* poly = vtkPolyData::SafeDownCast(dataset))
  {
    for (vtkCellArray* cells : { poly->GetVerts(), poly->GetLines(), poly->GetPolys(),
           poly->GetStrips() })
    {
      add(cells, cells ? cells->GetMTime() : 0);
    }
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(dataset))
  {
    add(grid->GetCells(), grid->GetCells() ? grid->GetCells()->GetMTime() : 0);
    add(grid->GetCellTypesArray(),
      grid->GetCellTypesArray() ? grid->GetCellTypesArray()->GetMTime() : 0);
  }
  else if (auto* image = vtkImageData::SafeDownCast(dataset))
  {
    int extent[6];
    image->GetExtent(extent);
    for (int v : extent)
    {
      print.push_back(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
    }
    for (int k = 0; k < 3; ++k)
    {
      addDouble(image->GetOrigin()[k]);
      addDouble(image->GetSpacing()[k]);
    }
    for (int k = 0; k < 9; ++k)
    {
      addDouble(image->GetDirectionMatrix()->GetData()[k]);
    }
  }
  else if (auto* rectilinear = vtkRectilinearGrid::SafeDownCast(dataset))
  {
    for (vtkDataArray* c : { rectilinear->GetXCoordinates(), rectilinear->GetYCoordinates(),
           rectilinear->GetZCoordinates() })
    {
      add(c, c ? c->GetMTime() : 0);
    }
    int extent[6];
    rectilinear->GetExtent(extent);
    for (int v : extent)
    {
      print.push_back(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
    }
  }
  else
  {
    // Another structured type: its own time (conservative: at worst a
    // refinement starts afresh).
    add(dataset, dataset->GetMTime());
  }
}

void AppendString(const std::string& s, std::vector<std::uint64_t>& print)
{
  print.push_back(s.size());
  for (std::size_t at = 0; at < s.size(); at += 8)
  {
    std::uint64_t word = 0;
    std::memcpy(&word, s.data() + at, std::min<std::size_t>(8, s.size() - at));
    print.push_back(word);
  }
}

void AppendDouble(double v, std::vector<std::uint64_t>& print)
{
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  print.push_back(bits);
}
} // namespace gridfree
