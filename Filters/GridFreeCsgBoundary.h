// Constructive solid geometry of several boundary operands (paper "Monte
// Carlo Geometry Processing", Sec. 5.1.4): closed meshes (each the blocks of
// a composite Boundary input) and an implicit function, combined by union,
// intersection or difference, hard or smoothly blended.
//
// Each mesh becomes a signed distance (MeshSignedDistance: the exact BVH
// distance, its sign by ray parity), the implicit function keeps its
// Lipschitz bound, and the combination is a CsgDistance tree, whose value is
// never above the distance to the combined surface: walks stay unbiased.
// Operands are folded left to right, ((A op B) op C) …, except that a
// difference removes all the others from the first: A − (B ∪ C ∪ …). Parts
// are numbered like the operands, which is how a walk that ends on the
// combined surface finds the operand whose values it takes.
// Private to the GridFree::Filters module.
#ifndef GridFreeCsgBoundary_h
#define GridFreeCsgBoundary_h

#include <gridfree/boundary/Boundary.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/SignedDistance.h>

#include <memory>
#include <string>
#include <vector>

class vtkDataArray;
class vtkPolyData;

namespace gridfree
{
// One mesh operand and, unless values come from an expression, its boundary
// values (g, or g and h side by side for the biharmonic equation).
struct CsgMeshOperand
{
  vtkPolyData* Mesh = nullptr;
  vtkDataArray* Values = nullptr;
  bool CellData = false;
};

struct CsgBoundaryReport
{
  long long DegenerateCells = 0;
  long long SkippedCells = 0;
  long long IgnoredLowerDimensionalCells = 0;
};

// Builds the combined boundary into `out`. `implicitOperand` (may be null)
// is the last operand. Values: `expressionValues` when given; otherwise each
// mesh operand's own values, sampled at its closest point to where a walk
// ends (an implicit operand then needs `expressionValues`). `probeBox`
// bounds the problem when the combination is unbounded (a half-space).
// Returns false with a reason for unusable input.
template <int DIM>
bool BuildCsgBoundary(const std::vector<CsgMeshOperand>& meshes,
  std::shared_ptr<const SignedDistanceFunction<DIM>> implicitOperand, CsgOperation operation,
  double blendRadius, std::shared_ptr<const BoundaryValueFunction<DIM>> expressionValues,
  const BoundingBox<DIM>& probeBox, Boundary<DIM>& out, CsgBoundaryReport& report,
  std::string& reason);

extern template bool BuildCsgBoundary<2>(const std::vector<CsgMeshOperand>&,
  std::shared_ptr<const SignedDistanceFunction<2>>, CsgOperation, double,
  std::shared_ptr<const BoundaryValueFunction<2>>, const BoundingBox<2>&, Boundary<2>&,
  CsgBoundaryReport&, std::string&);
extern template bool BuildCsgBoundary<3>(const std::vector<CsgMeshOperand>&,
  std::shared_ptr<const SignedDistanceFunction<3>>, CsgOperation, double,
  std::shared_ptr<const BoundaryValueFunction<3>>, const BoundingBox<3>&, Boundary<3>&,
  CsgBoundaryReport&, std::string&);
} // namespace gridfree

#endif
