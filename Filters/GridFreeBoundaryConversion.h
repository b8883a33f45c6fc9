// Turns a vtkPolyData boundary and its value array into the estimator core's
// Boundary<DIM>: triangles (3D) or segments (2D) plus the values on them.
// Private to the GridFree::Filters module.
#ifndef GridFreeBoundaryConversion_h
#define GridFreeBoundaryConversion_h

#include "Boundary.h"

#include <memory>
#include <string>

class vtkDataArray;
class vtkPolyData;

namespace gridfree
{
struct BoundaryConversionReport
{
  // Cells that were skipped because they have too few points to bound anything.
  long long SkippedCells = 0;
  // Lines/vertices ignored in a 3D boundary (which is made of surfaces).
  long long IgnoredLowerDimensionalCells = 0;
};

// The problem's dimension: 3 if the boundary has polygons or strips, 2 if it
// has only lines that all lie in one z-plane, 0 (with a reason) otherwise.
int DetectBoundaryDimension(vtkPolyData* boundary, std::string& reason);

// Fills `out` from the boundary's cells of the right kind and `values`
// (`cellData` tells whether values are per cell), or, when `valueFunction` is
// given, with values from that function instead (`values` is then unused).
// Returns false with a reason when nothing usable is left.
template <int DIM>
bool ConvertBoundary(vtkPolyData* boundary, vtkDataArray* values, bool cellData,
  Boundary<DIM>& out, BoundaryConversionReport& report, std::string& reason,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction = nullptr);

extern template bool ConvertBoundary<2>(vtkPolyData*, vtkDataArray*, bool, Boundary<2>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<2>>);
extern template bool ConvertBoundary<3>(vtkPolyData*, vtkDataArray*, bool, Boundary<3>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<3>>);
} // namespace gridfree

#endif
