// Turns a vtkPolyData boundary with a boundary condition per cell (or per
// point) into the core's MixedBoundary (Core/gridfree/stars/MixedBoundary.h),
// the boundary of walk on stars (Documentation/WalkOnStars.md):
//
//   condition 0  Dirichlet  u = g                 g: the boundary values
//   condition 1  Neumann    ∂u/∂n = h             h: the flux array (0 if none)
//   condition 2  Robin      ∂u/∂n + μ u = h       μ: the Robin coefficient array
//
// with n the outward normal. A condition given per point applies to a cell
// when all its points agree, and otherwise the smallest one wins: a cell is
// Neumann or Robin only where all its points are, so a region marked on the
// points keeps Dirichlet cells along its border. A Robin coefficient given
// per point is averaged over a cell's points.
//
// The Neumann and Robin cells must be oriented with outward normals (VTK's
// usual counter-clockwise order seen from outside; in 2D the domain on the
// left of every segment): the flux is taken along that normal and walks
// reflect off its inner side.
// Private to the GridFree::Filters module.
#ifndef GridFreeMixedBoundaryConversion_h
#define GridFreeMixedBoundaryConversion_h

#include "GridFreeBoundaryConversion.h"

#include <gridfree/stars/MixedBoundary.h>

#include <functional>
#include <memory>
#include <string>

class vtkDataArray;
class vtkPolyData;

namespace gridfree
{
// The arrays of a mixed boundary, each a point array or (…OnCells) a cell
// array of the boundary mesh.
struct MixedBoundaryArrays
{
  vtkDataArray* Values = nullptr; // g; unused when a value function gives it
  bool ValuesOnCells = false;
  vtkDataArray* Conditions = nullptr; // 0, 1 or 2, one component
  bool ConditionsOnCells = true;
  vtkDataArray* Flux = nullptr; // h, as many components as g; null: h = 0
  bool FluxOnCells = false;
  vtkDataArray* Robin = nullptr; // μ >= 0, one component; needed by Robin cells
  bool RobinOnCells = true;
};

// How many of the boundary's primitives (triangles, segments) took each
// condition.
struct MixedBoundaryCounts
{
  long long Dirichlet = 0;
  long long Neumann = 0;
  long long Robin = 0;
  long long Sheets = 0; // insulating sheets (3)
  double LargestFlux = 0.0;  // |h| on the Neumann and Robin cells
  double LargestValue = 0.0; // |g| in the boundary value array (0 with a value function)
  double Size = 0.0;         // the boundary's bounding-box diagonal
};

// Fills `out` from the boundary's cells and arrays, with g from
// `valueFunction` when it is given. False with a reason when the arrays do
// not fit (a condition other than 0, 1, 2 or 3; a flux of other components
// than g, or not finite where it is used; Robin cells without
// coefficients, or a negative or non-finite one: the first named, the
// others counted) or nothing usable is left. `whileBuilding` as for ConvertBoundary.
template <int DIM>
bool ConvertMixedBoundary(vtkPolyData* boundary, const MixedBoundaryArrays& arrays,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction, MixedBoundary<DIM>& out,
  BoundaryConversionReport& report, MixedBoundaryCounts& counts, std::string& reason,
  const std::function<void(double)>& whileBuilding = nullptr);

extern template bool ConvertMixedBoundary<2>(vtkPolyData*, const MixedBoundaryArrays&,
  std::shared_ptr<const BoundaryValueFunction<2>>, MixedBoundary<2>&, BoundaryConversionReport&,
  MixedBoundaryCounts&, std::string&, const std::function<void(double)>&);
extern template bool ConvertMixedBoundary<3>(vtkPolyData*, const MixedBoundaryArrays&,
  std::shared_ptr<const BoundaryValueFunction<3>>, MixedBoundary<3>&, BoundaryConversionReport&,
  MixedBoundaryCounts&, std::string&, const std::function<void(double)>&);
} // namespace gridfree

#endif
