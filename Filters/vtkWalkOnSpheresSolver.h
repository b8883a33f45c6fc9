/**
 * @class   vtkWalkOnSpheresSolver
 * @brief   Solve a Laplace boundary-value problem by walk on spheres, directly
 *          on a boundary surface, at the points of any probe dataset.
 *
 * vtkWalkOnSpheresSolver estimates the harmonic function u (Δu = 0) that takes
 * prescribed values g on a boundary, without a volume mesh: from every probe
 * point it runs independent random walks that jump to a uniform point on the
 * largest empty sphere until they come within Epsilon of the boundary, and
 * averages g at the closest boundary point (Sawhney & Crane 2020, Sec. 2.2).
 *
 * Input port 0, "Boundary", is a vtkPolyData. Triangles, polygons and triangle
 * strips make a 3D problem (a polygon soup is fine: no watertightness,
 * manifoldness or orientation is assumed). A boundary made only of lines and
 * polylines that lie in one z-plane makes a 2D problem in that plane. The
 * boundary values g are the array chosen with SetInputArrayToProcess(0, ...):
 * point data are interpolated linearly at the closest point, cell data are
 * constant per cell, and every component of a multi-component array is
 * estimated from the same walks. Without a selection, the active point (then
 * cell) scalars are used.
 *
 * Input port 1, "Probe", is any vtkDataSet; the output has the probe's type,
 * structure and arrays (an image stays an image), plus, for a boundary array
 * named T:
 * - `T`: the estimated solution (active scalars);
 * - `T_Variance`: the variance of that Monte Carlo mean (s^2/N), per component;
 * - `WalkSteps`: mean number of steps per walk;
 * - `EscapedFraction`: fraction of walks that left a far sphere around the
 *   boundary (only in a region the boundary does not enclose; they count as 0,
 *   the value at infinity);
 * - `TruncatedFraction`: fraction of walks stopped at MaxSteps (they take the
 *   value at their current closest boundary point).
 * Field data `TotalWalks`, `TotalSteps`, `EscapedWalks`, `TruncatedWalks` and
 * `SolveSeconds` summarize the run.
 *
 * Results are reproducible: a walk's random stream depends only on Seed, the
 * probe point's coordinates and the walk's number, so the output is identical
 * for any NumberOfThreads and any partition of the probe.
 *
 * @sa vtkProbeFilter
 */
#ifndef vtkWalkOnSpheresSolver_h
#define vtkWalkOnSpheresSolver_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

#include <cstdint> // for std::uint64_t

class vtkPolyData;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresSolver : public vtkDataSetAlgorithm
{
public:
  static vtkWalkOnSpheresSolver* New();
  vtkTypeMacro(vtkWalkOnSpheresSolver, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Convenience: connect the boundary (port 0) and the probe (port 1).
   */
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  void SetProbeConnection(vtkAlgorithmOutput* output);
  void SetProbeData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Number of random walks per probe point (default 128, at least 2 so a
   * variance can be reported). The standard error falls as 1/sqrt(walks).
   */
  vtkSetClampMacro(WalksPerPoint, int, 2, VTK_INT_MAX);
  vtkGetMacro(WalksPerPoint, int);
  ///@}

  ///@{
  /**
   * Stopping tolerance: a walk ends once it is closer than Epsilon to the
   * boundary. Relative to the boundary's bounding-box diagonal when
   * EpsilonIsRelative is on (the default, 1e-4), otherwise in world units.
   * The solution's bias is O(Epsilon); cost grows only like log(1/Epsilon).
   */
  vtkSetClampMacro(Epsilon, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Epsilon, double);
  vtkSetMacro(EpsilonIsRelative, bool);
  vtkGetMacro(EpsilonIsRelative, bool);
  vtkBooleanMacro(EpsilonIsRelative, bool);
  ///@}

  ///@{
  /**
   * Maximum number of steps of one walk (default 10000). Walks stopped here
   * are counted in TruncatedFraction and reported with a warning.
   */
  vtkSetClampMacro(MaxSteps, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaxSteps, int);
  ///@}

  ///@{
  /**
   * Seed of the random streams (default 0). The same seed gives the same
   * numbers whatever the thread count.
   */
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /**
   * Number of threads (default 0: all available cores).
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * Statistics of the last execution: walks run, wall-clock seconds of the
   * solve, walks per second, dimension of the problem (2 or 3; 0 if none).
   */
  vtkGetMacro(LastNumberOfWalks, vtkIdType);
  vtkGetMacro(LastSolveSeconds, double);
  double GetLastWalksPerSecond() const;
  vtkGetMacro(LastDimension, int);
  ///@}

protected:
  vtkWalkOnSpheresSolver();
  ~vtkWalkOnSpheresSolver() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int WalksPerPoint = 128;
  double Epsilon = 1e-4;
  bool EpsilonIsRelative = true;
  int MaxSteps = 10000;
  int Seed = 0;
  int NumberOfThreads = 0;

  vtkIdType LastNumberOfWalks = 0;
  double LastSolveSeconds = 0.0;
  int LastDimension = 0;

private:
  vtkWalkOnSpheresSolver(const vtkWalkOnSpheresSolver&) = delete;
  void operator=(const vtkWalkOnSpheresSolver&) = delete;

  template <int DIM>
  friend class vtkWalkOnSpheresSolverRunner;
};

#endif
