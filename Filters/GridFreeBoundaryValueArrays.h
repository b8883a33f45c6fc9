// Resolves and checks the boundary values of a problem's Boundary input,
// or of each block of a CSG boundary: the selected array g (else the active
// scalars), h for the biharmonic equation and the back side's g for
// two-sided values, side by side in one array.
// Private to the GridFree::Filters module.
#ifndef GridFreeBoundaryValueArrays_h
#define GridFreeBoundaryValueArrays_h

#include "vtkSmartPointer.h"

#include <string>
#include <vector>

class vtkDataArray;
class vtkObject;
class vtkPolyData;

namespace gridfree
{
struct ArraySelections;
struct ProblemInputs;
struct SolveSettings;

// Whose arrays and settings are read, and whom errors are reported for.
struct BoundaryValueContext
{
  vtkObject* Reporter;
  const SolveSettings& Settings;
  const ArraySelections& Arrays;
};

// g (and h) of one mesh; `what` names it in messages. `combined` is null
// when the values come from expressions.
bool BoundaryValuesOfMesh(const BoundaryValueContext& context, vtkPolyData* mesh,
  const std::string& what, std::string& name, vtkSmartPointer<vtkDataArray>& combined,
  bool& cellData);
// The back side's values of two-sided boundary values (input array 3),
// side by side after the front's `values` in `combined`.
bool BackBoundaryValues(const BoundaryValueContext& context, vtkPolyData* mesh,
  const std::string& what, const std::string& name, vtkDataArray* values, int association,
  vtkSmartPointer<vtkDataArray>& combined);
// The problem's dimension and values for a single Boundary input.
bool BoundaryValuesOfBoundary(const BoundaryValueContext& context, vtkPolyData* boundary,
  bool implicit, bool expressionValues, int& dimension, std::string& name,
  vtkSmartPointer<vtkDataArray>& combined, bool& cellData);
// The operands of a CSG boundary: every block (and the implicit boundary)
// in one dimension, each block with its own values unless expressions
// give them.
bool BoundaryValuesOfCsgOperands(const BoundaryValueContext& context,
  const std::vector<vtkPolyData*>& blocks, bool expressionValues, ProblemInputs& inputs,
  int& dimension, std::string& name);
} // namespace gridfree

#endif
