// Small helpers for the arrays the GridFree filters read and write: new
// double arrays (NaN until written, so points an aborted run left without
// walks never show a plausible-looking zero), one-number field arrays (run
// summaries such as TotalWalks), and any numeric array as row-major doubles
// (the estimator core's layout).
// Private to the GridFree::Filters module.
#ifndef GridFreeArrays_h
#define GridFreeArrays_h

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <limits>
#include <string>
#include <vector>

namespace gridfree
{
inline vtkSmartPointer<vtkDoubleArray> MakeArray(
  const std::string& name, int components, vtkIdType tuples)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  array->Fill(std::numeric_limits<double>::quiet_NaN());
  return array;
}

inline void AddFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

// The tuples of `array` as row-major doubles.
inline std::vector<double> ToDoubles(vtkDataArray* array)
{
  const vtkIdType tuples = array->GetNumberOfTuples();
  const int components = array->GetNumberOfComponents();
  std::vector<double> result(static_cast<std::size_t>(tuples) * components);
  for (vtkIdType t = 0; t < tuples; ++t)
  {
    array->GetTuple(t, result.data() + static_cast<std::size_t>(t) * components);
  }
  return result;
}
} // namespace gridfree

#endif
