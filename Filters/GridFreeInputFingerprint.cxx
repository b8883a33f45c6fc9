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
#include <map>
#include <mutex>
#include <utility>

namespace gridfree
{
namespace
{
// A 64-bit hash of an array's values (with its type, name, components and
// tuples): eight bytes at a time, each word mixed in with a multiply and a
// shift, a few GB/s. Arrays without the standard contiguous layout
// (implicit, struct-of-arrays) and non-numeric ones hash by identity and
// modification time.
std::uint64_t HashContent(vtkAbstractArray* array)
{
  constexpr std::uint64_t kMultiplier = 0x9E3779B97F4A7C15ULL;
  std::uint64_t h = 0xCBF29CE484222325ULL;
  auto mix = [&h](std::uint64_t word) {
    h ^= word;
    h *= kMultiplier;
    h ^= h >> 29;
  };
  auto* data = vtkDataArray::SafeDownCast(array);
  if (!data || !data->HasStandardMemoryLayout())
  {
    mix(static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(array)));
    mix(static_cast<std::uint64_t>(array ? array->GetMTime() : 0));
    return h;
  }
  mix(static_cast<std::uint64_t>(data->GetDataType()));
  mix(static_cast<std::uint64_t>(data->GetNumberOfComponents()));
  mix(static_cast<std::uint64_t>(data->GetNumberOfTuples()));
  const char* name = data->GetName() ? data->GetName() : "";
  for (const char* c = name; *c; ++c)
  {
    mix(static_cast<unsigned char>(*c));
  }
  const auto* bytes = static_cast<const unsigned char*>(data->GetVoidPointer(0));
  const std::size_t size = static_cast<std::size_t>(data->GetNumberOfValues()) *
    static_cast<std::size_t>(data->GetDataTypeSize());
  std::size_t at = 0;
  for (; at + 8 <= size; at += 8)
  {
    std::uint64_t word;
    std::memcpy(&word, bytes + at, 8);
    mix(word);
  }
  std::uint64_t tail = 0;
  std::memcpy(&tail, bytes + at, size - at);
  mix(tail ^ (static_cast<std::uint64_t>(size) << 56));
  return h;
}

// The hash of an array's values, memoized by its address and modification
// time: an array that has not changed is hashed once, however often a
// filter is updated. (A new array at a freed one's address has a newer
// modification time: VTK's clock only moves forward.)
std::uint64_t ContentHash(vtkAbstractArray* array)
{
  static std::mutex mutex;
  static std::map<std::pair<const void*, vtkMTimeType>, std::uint64_t> memo;
  const auto key = std::make_pair(static_cast<const void*>(array), array->GetMTime());
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto found = memo.find(key);
    if (found != memo.end())
    {
      return found->second;
    }
  }
  const std::uint64_t hash = HashContent(array);
  std::lock_guard<std::mutex> lock(mutex);
  if (memo.size() >= 4096)
  {
    memo.clear(); // bounded: old entries are for arrays long gone
  }
  memo[key] = hash;
  return hash;
}
} // namespace

// What a dataset's content is made of: the values of its arrays (points,
// cells, point, cell and field data), and the values that define an
// image's or a rectilinear grid's geometry. Pipelines often hand a filter
// a fresh shallow copy of the same data (ParaView's vtkPVPostFilter does,
// at every update), and ParaView's first Apply after a script re-executes
// filters whose output is the same as before: new arrays with the same
// values, which must not look like a change; any real edit changes some
// array's values or these numbers.
void AppendFingerprint(vtkObject* object, std::vector<std::uint64_t>& print)
{
  auto add = [&print](const void* p, vtkMTimeType t) {
    print.push_back(static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p)));
    print.push_back(static_cast<std::uint64_t>(t));
  };
  auto addArray = [&print](vtkAbstractArray* a) {
    print.push_back(a ? ContentHash(a) : 0);
  };
  auto addCells = [&addArray](vtkCellArray* cells) {
    addArray(cells ? cells->GetOffsetsArray() : nullptr);
    addArray(cells ? cells->GetConnectivityArray() : nullptr);
  };
  auto addDouble = [&print](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    print.push_back(bits);
  };
  auto addAttributes = [&addArray](vtkFieldData* fd) {
    if (!fd)
    {
      return;
    }
    for (int k = 0; k < fd->GetNumberOfArrays(); ++k)
    {
      addArray(fd->GetAbstractArray(k));
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
    addArray(points ? points->GetData() : nullptr);
  }
  if (auto* poly = vtkPolyData::SafeDownCast(dataset))
  {
    for (vtkCellArray* cells : { poly->GetVerts(), poly->GetLines(), poly->GetPolys(),
           poly->GetStrips() })
    {
      addCells(cells);
    }
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(dataset))
  {
    addCells(grid->GetCells());
    addArray(grid->GetCellTypesArray());
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
      addArray(c);
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
