/**
 * @class   vtkBoundaryConditionMarker
 * @brief   Marks the boundary cells inside a region (behind a plane, in a
 *          box, sphere or cylinder) with a boundary condition (Neumann,
 *          Robin or insulating sheet) for the solver's Mixed Boundary
 *          Conditions, with no expression to write.
 *
 * The output is the input surface with three cell arrays, the ones the Walk
 * On Spheres Solver's mixed conditions read (it picks an array named bc by
 * itself): `bc` (0 Dirichlet, 1 Neumann, 2 Robin, 3 insulating sheet), `mu`
 * (the Robin coefficient) and `h` (the flux). Cells whose centre c has
 * Region(c) < 0 (inside a box, sphere or cylinder; behind a plane, on the
 * side its normal points away from), or > 0 with InsideOut, get Condition,
 * with RobinCoefficient in `mu` and Flux in `h`; the other cells keep the
 * input's `bc`, `mu` and `h` cell arrays where it has them (so markers can be
 * chained, one region each), or get 0 (Dirichlet). Field data MarkedCells
 * counts the cells marked. In ParaView the region is a widget to drag.
 *
 * @sa vtkWalkOnSpheresSolver
 */
#ifndef vtkBoundaryConditionMarker_h
#define vtkBoundaryConditionMarker_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class vtkImplicitFunction;

class GRIDFREEFILTERS_EXPORT vtkBoundaryConditionMarker : public vtkPolyDataAlgorithm
{
public:
  static vtkBoundaryConditionMarker* New();
  vtkTypeMacro(vtkBoundaryConditionMarker, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Conditions, as the solver's boundary condition array holds them.
  enum ConditionType
  {
    DIRICHLET = 0,
    NEUMANN = 1,
    ROBIN = 2,
    INSULATING_SHEET = 3
  };

  ///@{
  /**
   * The condition given to the marked cells (default NEUMANN).
   */
  vtkSetClampMacro(Condition, int, DIRICHLET, INSULATING_SHEET);
  vtkGetMacro(Condition, int);
  ///@}

  ///@{
  /**
   * The region: an implicit function, negative inside (vtkPlane, vtkBox,
   * vtkSphere, vtkCylinder, ...); none is an error. InsideOut (default off)
   * marks where it is positive instead.
   */
  void SetRegion(vtkImplicitFunction* region);
  vtkGetObjectMacro(Region, vtkImplicitFunction);
  vtkSetMacro(InsideOut, bool);
  vtkGetMacro(InsideOut, bool);
  vtkBooleanMacro(InsideOut, bool);
  ///@}

  /**
   * Includes the region's MTime.
   */
  vtkMTimeType GetMTime() override;

  ///@{
  /**
   * The Robin coefficient (>= 0, default 1) written to `mu` on marked cells
   * when Condition is ROBIN (0 otherwise), and the flux (default 0: an
   * insulated wall) written to `h` on marked Neumann and Robin cells.
   */
  vtkSetClampMacro(RobinCoefficient, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(RobinCoefficient, double);
  vtkSetMacro(Flux, double);
  vtkGetMacro(Flux, double);
  ///@}

protected:
  vtkBoundaryConditionMarker() = default;
  ~vtkBoundaryConditionMarker() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkBoundaryConditionMarker(const vtkBoundaryConditionMarker&) = delete;
  void operator=(const vtkBoundaryConditionMarker&) = delete;

  int Condition = NEUMANN;
  vtkImplicitFunction* Region = nullptr;
  bool InsideOut = false;
  double RobinCoefficient = 1.0;
  double Flux = 0.0;
};

#endif
