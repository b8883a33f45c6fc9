/**
 * @class   vtkWalkOnSpheresProbeAlgorithm
 * @brief   Base of the application filters (Helmholtz decomposition, cross
 *          fields, deformation) that solve with walk on spheres inside a
 *          Boundary and give their results on a Probe dataset.
 *
 * Input 0 ("Boundary") is a vtkPolyData: triangles or polygons for a 3D
 * domain, lines (or Bézier control polygons, see vtkWalkOnSpheresSolver) in
 * one z-plane for a 2D one. Input 1 ("Probe") is any vtkDataSet; output 0 is
 * a copy of it (same type, structure and arrays) with the results added.
 * Further inputs and outputs belong to the subclass.
 *
 * The sampling settings (vtkWalkOnSpheresAlgorithm's: walks, default 256
 * here, ε, steps, seed, threads) configure the solves the subclass makes:
 * each builds its problem and asks it at the probe's points directly, with
 * no internal pipeline. Each solve of the subclass keeps its built boundary
 * (hierarchy and values) between executions, so a moved probe, other walks
 * or another seed never rebuild it (GetLastBoundaryBuilt tells). Progress
 * of the solves is reported as this filter's, and aborting this filter
 * aborts them.
 *
 * @sa vtkWalkOnSpheresAlgorithm vtkWalkOnSpheresSolver vtkWalkOnSpheresHelmholtzDecomposition
 */
#ifndef vtkWalkOnSpheresProbeAlgorithm_h
#define vtkWalkOnSpheresProbeAlgorithm_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresAlgorithm.h"
#include "vtkSmartPointer.h"         // for vtkSmartPointer

#include <array>      // for std::array
#include <functional> // for std::function
#include <string>
#include <vector>     // for std::vector

class vtkAlgorithmOutput;
class vtkDataObject;
class vtkDataSet;
namespace gridfree
{
struct ArraySelections;
struct BuiltProblem;
struct PointNumbers;
struct PointEstimateRun;
struct PointEstimateSummary;
struct SolveSettings;
}

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresProbeAlgorithm : public vtkWalkOnSpheresAlgorithm
{
public:
  vtkTypeMacro(vtkWalkOnSpheresProbeAlgorithm, vtkWalkOnSpheresAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The Boundary (port 0) and the Probe (port 1).
   */
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  void SetProbeConnection(vtkAlgorithmOutput* output);
  void SetProbeData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Walks and seconds of the last execution, over all its solves.
   */
  vtkGetMacro(LastNumberOfWalks, vtkIdType);
  vtkGetMacro(LastSolveSeconds, double);
  ///@}

protected:
  vtkWalkOnSpheresProbeAlgorithm();
  ~vtkWalkOnSpheresProbeAlgorithm() override;

  static constexpr int BoundaryPort = 0;
  static constexpr int ProbePort = 1;

  // Port 0: vtkPolyData; port 1: vtkDataSet; other ports: an optional
  // vtkDataSet.
  int FillInputPortInformation(int port, vtkInformation* info) override;
  // Output 0 takes the probe's type; other outputs the type their port
  // information names (vtkPolyData by default).
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // The probe is split as output 0 is; every other input is needed whole.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // One solve for the subclass, with no internal pipeline: the problem of
  // `boundary` (its arrays chosen by `arrays`) and the optional `source`
  // with `settings`, estimated at `probe`'s points. `result` becomes a copy
  // of the probe with the solution arrays, named as vtkWalkOnSpheresSolver's
  // output. Progress is reported as [begin, end] of this filter's; walks and
  // seconds are added to the Last... counters (the subclass resets them);
  // each distinct warning is reported once. False after an error (reported
  // as this filter's) or when aborted (`aborted` tells which). `problem`
  // names the subclass's solve (0, 1, ... for solves of different boundary
  // values): each keeps its built boundary for the next execution's solve
  // of the same number, and reuses it while it is built from the same data.
  bool Solve(const gridfree::SolveSettings& settings, const gridfree::ArraySelections& arrays,
    vtkDataObject* boundary, vtkDataObject* source, vtkDataSet* probe, double begin, double end,
    vtkSmartPointer<vtkDataSet>& result, bool& aborted, int problem = 0);
  // The same solve for a subclass that uses the numbers itself: they stay in
  // `found` (the core's numbers, GridFreePointNumbers.h), and no
  // copy of `where` is made.
  bool SolveNumbers(const gridfree::SolveSettings& settings,
    const gridfree::ArraySelections& arrays, vtkDataObject* boundary, vtkDataObject* source,
    vtkDataSet* where, double begin, double end, gridfree::PointNumbers& found, bool& aborted,
    int problem = 0);

  // Adds the Last... counters to `output`'s field data (TotalWalks,
  // SolveSeconds).
  void AddSummary(vtkDataObject* output);

  vtkIdType LastNumberOfWalks = 0;
  double LastSolveSeconds = 0.0;

private:
  vtkWalkOnSpheresProbeAlgorithm(const vtkWalkOnSpheresProbeAlgorithm&) = delete;
  void operator=(const vtkWalkOnSpheresProbeAlgorithm&) = delete;

  // A solve's batch at its points, given the built problem.
  using BatchRunner = std::function<bool(const gridfree::BuiltProblem&,
    const std::vector<std::array<double, 3>>&, const gridfree::PointEstimateRun&,
    gridfree::PointEstimateSummary&)>;
  // Builds (or reuses) problem number `problem` and runs `estimate` with this
  // filter's progress range, counters and warnings.
  bool RunSolve(const gridfree::SolveSettings& settings, const gridfree::ArraySelections& arrays,
    vtkDataObject* boundary, vtkDataObject* source, vtkDataSet* probe, double begin, double end,
    bool& aborted, int problem, const BatchRunner& estimate);

};

#endif
