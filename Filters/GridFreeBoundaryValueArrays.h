// Resolves and checks the boundary values of the solver's Boundary input,
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
class vtkPolyData;
class vtkWalkOnSpheresSolver;
struct vtkWalkOnSpheresSolverInputs;

// A friend of vtkWalkOnSpheresSolver: it reads the selected input arrays.
class vtkWalkOnSpheresSolverBoundaryValues
{
public:
  // g (and h) of one mesh; `what` names it in messages. `combined` is null
  // when the values come from expressions.
  static bool OfMesh(vtkWalkOnSpheresSolver* self, vtkPolyData* mesh, const std::string& what,
    std::string& name, vtkSmartPointer<vtkDataArray>& combined, bool& cellData);

  // The back side's values of two-sided boundary values (input array 3),
  // side by side after the front's `values` in `combined`.
  static bool BackValues(vtkWalkOnSpheresSolver* self, vtkPolyData* mesh, const std::string& what,
    const std::string& name, vtkDataArray* values, int association,
    vtkSmartPointer<vtkDataArray>& combined);

  // The problem's dimension and values for a single Boundary input.
  static bool OfBoundary(vtkWalkOnSpheresSolver* self, vtkPolyData* boundary, bool implicit,
    bool expressionValues, int& dimension, std::string& name,
    vtkSmartPointer<vtkDataArray>& combined, bool& cellData);

  // The operands of a CSG boundary: every block (and the implicit boundary)
  // in one dimension, each block with its own values unless expressions
  // give them.
  static bool OfCsgOperands(vtkWalkOnSpheresSolver* self, const std::vector<vtkPolyData*>& blocks,
    bool expressionValues, vtkWalkOnSpheresSolverInputs& inputs, int& dimension, std::string& name);
};

#endif
