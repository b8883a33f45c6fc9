// What the problem builder resolved from a filter's inputs and settings,
// handed to the boundary assembly and the source conversion.
// Private to the GridFree::Filters module.
#ifndef GridFreeProblemInputs_h
#define GridFreeProblemInputs_h

#include "GridFreeCsgBoundary.h"
#include "vtkSmartPointer.h"

#include <gridfree/implicit/CsgOperation.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

class vtkDataArray;
class vtkDataSet;
class vtkImageData;
class vtkImplicitFunction;
class vtkPolyData;

namespace gridfree
{
struct ProblemInputs
{
  vtkPolyData* Boundary = nullptr; // the mesh, or the value carrier of an implicit boundary
  vtkImplicitFunction* Implicit = nullptr;
  // CSG: the blocks as operands (with their values unless expressions give
  // them), combined with Implicit, if set, as the last operand.
  std::vector<gridfree::CsgMeshOperand> CsgOperands;
  std::optional<gridfree::CsgOperation> CsgOperation; // none: one soup
  double CsgBlendRadius = 0.0;
  double LipschitzBound = 1.0; // of an implicit function not known to be a distance
  std::vector<vtkSmartPointer<vtkDataArray>> CsgValues; // keeps the operands' values alive
  std::vector<std::string> ValueExpressions; // g (and h), replacing Values when set
  vtkDataArray* Values = nullptr; // g, or g and h side by side (biharmonic)
  bool CellData = false;
  bool TwoSided = false; // Values holds the front's then the back's g
  // Mixed conditions (walk on stars): the condition per cell or point, the
  // Neumann flux (null: 0) and the Robin coefficient (null: no Robin cells).
  bool Mixed = false;
  vtkDataArray* Conditions = nullptr;
  bool ConditionsOnCells = true;
  vtkDataArray* Flux = nullptr;
  bool FluxOnCells = false;
  vtkDataArray* Robin = nullptr;
  bool RobinOnCells = true;

  vtkDataSet* Source = nullptr;
  vtkDataArray* SourceArray = nullptr;
  // The equation with varying coefficients: the image its arrays lie on
  // (null: constants only), α (selection 7), σ (8) and f (2), each null
  // for the setting's constant (f: 0).
  vtkImageData* CoefficientImage = nullptr;
  vtkDataArray* DiffusionArray = nullptr;
  vtkDataArray* AbsorptionArray = nullptr;
  vtkDataArray* CoefficientSourceArray = nullptr;
  std::string Expression;
  // The points the problem is asked about: implicit and CSG boundaries are
  // built in a region around them.
  vtkDataSet* Region = nullptr;
  std::string Name;
  // What the core boundary is built from (GridFreeProblemBuilder's cache).
  std::vector<std::uint64_t> BoundaryKey;
};
} // namespace gridfree

#endif
