// Turns a vtkPolyData boundary and its value array into the estimator core's
// Boundary<DIM>: triangles (3D) or segments (2D) plus the values on them, or,
// for a 2D boundary with Bézier curves, a BezierBoundaryGeometry.
// Private to the GridFree::Filters module.
//
// Bézier curves (2D only). A polyline whose value in the cell array named
// BezierControlPointsArrayName is nonzero lists the control points of a
// piecewise cubic Bézier curve, P0 P1 P2 P3 P4 P5 P6 …: 3k + 1 points for k
// curves, consecutive curves sharing their end point (P3 ends the first curve
// and starts the second). Polylines with value 0, or all polylines when there
// is no such array, are straight segments. As soon as one Bézier polyline is
// present the whole boundary becomes Bézier curves, each straight segment an
// exactly straight cubic (inner control points at 1/3 and 2/3, so t runs
// linearly along it). Point values are interpolated linearly in t between a
// curve's end points P0 and P3 (inner handles are off the curve, their values
// are not used); cell values are constant on a polyline.
#ifndef GridFreeBoundaryConversion_h
#define GridFreeBoundaryConversion_h

#include <gridfree/boundary/Boundary.h>

#include "vtkType.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

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
  // Primitives dropped because they cover no length or area: segments whose
  // two points coincide, triangles (after triangulating polygons and strips)
  // whose edge cross product is exactly zero, and Bézier curves whose four
  // control points coincide. Counted per segment, triangle or curve.
  long long DegenerateCells = 0;
};

// Name of the cell array that marks polylines of Bézier control points.
extern const char* const BezierControlPointsArrayName;

// The problem's dimension: 3 if the boundary has polygons or strips, 2 if it
// has only lines that all lie in one z-plane, 0 (with a reason) otherwise.
int DetectBoundaryDimension(vtkPolyData* boundary, std::string& reason);

// A boundary's cells as the core's primitives, before any values.
template <int DIM>
struct BoundaryCells
{
  std::vector<Vec<DIM>> Vertices; // the input's points, all of them, in order
  std::vector<typename Boundary<DIM>::Primitive> Primitives;
  std::vector<vtkIdType> SourceCell; // the input cell each primitive came from
};

// The cells of the right kind (3D: polygons, triangulated, and strips; 2D:
// line segments) as primitives, without degenerate ones (counted in
// `report`). False with a reason when nothing usable is left, a point id or
// coordinate is invalid, or a 2D boundary has Bézier curves.
template <int DIM>
bool CollectBoundaryCells(vtkPolyData* boundary, BoundaryCells<DIM>& cells,
  BoundaryConversionReport& report, std::string& reason);

// Fills `out` from the boundary's cells of the right kind and `values`
// (`cellData` tells whether values are per cell), or, when `valueFunction` is
// given, with values from that function instead (`values` is then unused).
// Returns false with a reason when nothing usable is left. With
// `whileBuilding`, the VTK-free part (welding vertices, the hierarchy and the
// distance bounds, seconds on a large mesh) runs on a thread of its own while
// whileBuilding(seconds elapsed) is called on this one about ten times a
// second, for progress reports.
template <int DIM>
bool ConvertBoundary(vtkPolyData* boundary, vtkDataArray* values, bool cellData,
  Boundary<DIM>& out, BoundaryConversionReport& report, std::string& reason,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction = nullptr,
  const std::function<void(double)>& whileBuilding = nullptr);

extern template bool CollectBoundaryCells<2>(
  vtkPolyData*, BoundaryCells<2>&, BoundaryConversionReport&, std::string&);
extern template bool CollectBoundaryCells<3>(
  vtkPolyData*, BoundaryCells<3>&, BoundaryConversionReport&, std::string&);
extern template bool ConvertBoundary<2>(vtkPolyData*, vtkDataArray*, bool, Boundary<2>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<2>>,
  const std::function<void(double)>&);
extern template bool ConvertBoundary<3>(vtkPolyData*, vtkDataArray*, bool, Boundary<3>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<3>>,
  const std::function<void(double)>&);
} // namespace gridfree

#endif
