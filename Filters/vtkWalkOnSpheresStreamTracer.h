/**
 * @class   vtkWalkOnSpheresStreamTracer
 * @brief   Streamlines of the gradient of a walk-on-spheres solution, with no
 *          grid solve (output-sensitive, paper Sec. 5.2.6).
 *
 * Input 0 ("Boundary") is the solver's boundary (see vtkWalkOnSpheresSolver),
 * input 1 ("Seeds") any dataset whose points start the lines, input 2
 * ("Source", optional) the solver's source term. Each line follows the unit
 * gradient direction of the solution u (∇u/|∇u|, or −∇u/|∇u| backward) with
 * a fixed step, by Heun's method (two gradient estimates per step) or the
 * classical Runge–Kutta method (four). The gradient is estimated only at the
 * integrator's points, all lines advancing together: the problem is built
 * once per execution (see vtkWalkOnSpheresSolverDriver for the equation,
 * walks, epsilon, seed...; the boundary array is the one selected on this
 * filter with SetInputArrayToProcess(0, ...)) and asked for each stage's
 * points directly. An implicit boundary is built around the seeds.
 *
 * A step never leaves the empty ball around the line's point (it is at most
 * half the distance to the boundary, which the solver outputs as
 * BoundaryDistance), so lines never cross the boundary: near it, steps
 * shrink. A line ends after MaximumNumberOfSteps steps or MaximumPropagation
 * length, where |∇u| falls below TerminalSpeed, where it comes closer than
 * the solver's epsilon to the boundary, or where it leaves the boundary's
 * bounding box (enlarged by one step). The output is a vtkPolyData of polylines, as
 * vtkStreamTracer's: point data `T`, `T_Variance`, `T_Gradient` (active
 * vectors), `T_Gradient_Variance` (for a boundary array T) estimated at every
 * line point, and `IntegrationTime` (the arc length from the seed, negative
 * backward); cell data `SeedIds` and `ReasonForTermination`; field data
 * `TotalWalks` and `SolveSeconds` over all the lines
 * (vtkStreamTracer's codes: OUT_OF_DOMAIN 1, STAGNATION 4 (below
 * TerminalSpeed), OUT_OF_LENGTH 2, OUT_OF_STEPS 3, plus CLOSE_TO_BOUNDARY 7).
 *
 * Reproducible like the solver: the same seed gives the same lines for any
 * thread count. The walks at different points are independent, so a line's
 * noise does not average out along it: use enough walks per point that the
 * gradient's standard error is small against |∇u|.
 *
 * @sa vtkWalkOnSpheresSolver vtkStreamTracer
 */
#ifndef vtkWalkOnSpheresStreamTracer_h
#define vtkWalkOnSpheresStreamTracer_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresSolverDriver.h"

class vtkAlgorithmOutput;
class vtkDataObject;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresStreamTracer : public vtkWalkOnSpheresSolverDriver
{
public:
  static vtkWalkOnSpheresStreamTracer* New();
  vtkTypeMacro(vtkWalkOnSpheresStreamTracer, vtkWalkOnSpheresSolverDriver);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Direction
  {
    FORWARD = 0,
    BACKWARD = 1,
    BOTH = 2
  };

  enum Integrator
  {
    HEUN = 0,
    RUNGE_KUTTA_4 = 1
  };

  enum Reason
  {
    OUT_OF_DOMAIN = 1,
    OUT_OF_LENGTH = 2,
    OUT_OF_STEPS = 3,
    STAGNATION = 4,
    CLOSE_TO_BOUNDARY = 7
  };

  ///@{
  /**
   * The seeds (port 1). Boundary (port 0) and Source (port 2): see
   * vtkWalkOnSpheresSolverDriver, which also holds the solve's settings.
   */
  void SetSeedsConnection(vtkAlgorithmOutput* output);
  void SetSeedsData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Step length, relative to the boundary's bounding-box diagonal (default
   * 0.01) or in world units when StepLengthIsRelative is off.
   */
  vtkSetClampMacro(StepLength, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(StepLength, double);
  vtkSetMacro(StepLengthIsRelative, bool);
  vtkGetMacro(StepLengthIsRelative, bool);
  vtkBooleanMacro(StepLengthIsRelative, bool);
  ///@}

  ///@{
  /**
   * Limits of a line: steps (default 200) and length, in the units of the
   * step length (default 1, i.e. the boundary's diagonal when relative).
   */
  vtkSetClampMacro(MaximumNumberOfSteps, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumNumberOfSteps, int);
  vtkSetClampMacro(MaximumPropagation, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumPropagation, double);
  ///@}

  ///@{
  /**
   * A line stops where |∇u| falls below this (default 0: only where the
   * estimate is exactly zero).
   */
  vtkSetClampMacro(TerminalSpeed, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TerminalSpeed, double);
  ///@}

  ///@{
  /**
   * Up the gradient (FORWARD, the default), down it (BACKWARD) or both.
   */
  vtkSetClampMacro(IntegrationDirection, int, FORWARD, BOTH);
  vtkGetMacro(IntegrationDirection, int);
  ///@}

  ///@{
  /**
   * HEUN (default; two estimates per step) or RUNGE_KUTTA_4 (four).
   */
  vtkSetClampMacro(IntegratorType, int, HEUN, RUNGE_KUTTA_4);
  vtkGetMacro(IntegratorType, int);
  ///@}

  /**
   * Gradient estimates (probe points) of the last execution.
   */
  vtkGetMacro(LastNumberOfEstimates, vtkIdType);

protected:
  vtkWalkOnSpheresStreamTracer();
  ~vtkWalkOnSpheresStreamTracer() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double StepLength = 0.01;
  bool StepLengthIsRelative = true;
  int MaximumNumberOfSteps = 200;
  double MaximumPropagation = 1.0;
  double TerminalSpeed = 0.0;
  int IntegrationDirection = FORWARD;
  int IntegratorType = HEUN;
  vtkIdType LastNumberOfEstimates = 0;

private:
  vtkWalkOnSpheresStreamTracer(const vtkWalkOnSpheresStreamTracer&) = delete;
  void operator=(const vtkWalkOnSpheresStreamTracer&) = delete;
};

#endif
