/**
 * @class   vtkWalkOnSpheresAlgorithm
 * @brief   Base of every GridFree filter that solves: it keeps their
 *          settings and their built problems between executions.
 *
 * The Walk On Spheres Solver, the stream tracer and the adaptive sampler
 * (through vtkWalkOnSpheresSolverDriver) and the application filters
 * (through vtkWalkOnSpheresProbeAlgorithm) derive from it. It holds the filter's
 * settings in one gridfree::SolveSettings, with the sampling settings every
 * such filter shares (walks, ε, steps, seed, threads) as its properties, and
 * one problem builder per solve of the subclass: a builder keeps its built
 * boundary (hierarchy and values) while the data it is built from do not
 * change, so a second execution with moved points, other walks or another
 * seed rebuilds nothing (GetLastBoundaryBuilt tells).
 *
 * @sa vtkWalkOnSpheresSolver vtkWalkOnSpheresSolverDriver vtkWalkOnSpheresProbeAlgorithm
 */
#ifndef vtkWalkOnSpheresAlgorithm_h
#define vtkWalkOnSpheresAlgorithm_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

#include <memory> // for std::unique_ptr

namespace gridfree
{
struct ArraySelections;
struct BuiltProblem;
class ProblemBuilder;
struct ProblemData;
struct SolveSettings;
}

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresAlgorithm : public vtkDataSetAlgorithm
{
public:
  vtkTypeMacro(vtkWalkOnSpheresAlgorithm, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Random walks per point (at least 2; the default is the subclass's).
   */
  virtual void SetWalksPerPoint(int walks);
  int GetWalksPerPoint();
  ///@}

  ///@{
  /**
   * Stopping tolerance: a walk ends once it is closer than Epsilon to the
   * boundary. Relative to the boundary's bounding-box diagonal when
   * EpsilonIsRelative is on (the default, 1e-4), otherwise in world units.
   * The solution's bias is O(Epsilon); cost grows only like log(1/Epsilon).
   */
  void SetEpsilon(double epsilon);
  double GetEpsilon();
  void SetEpsilonIsRelative(bool relative);
  bool GetEpsilonIsRelative();
  void EpsilonIsRelativeOn() { this->SetEpsilonIsRelative(true); }
  void EpsilonIsRelativeOff() { this->SetEpsilonIsRelative(false); }
  ///@}

  ///@{
  /**
   * Maximum number of steps of one walk (default 10000). Walks stopped here
   * are counted in TruncatedFraction and reported with a warning.
   */
  void SetMaxSteps(int steps);
  int GetMaxSteps();
  ///@}

  ///@{
  /**
   * Seed of the random streams (default 0). Results depend on the seed and
   * the points' coordinates only, never on the thread count.
   */
  void SetSeed(int seed);
  int GetSeed();
  ///@}

  ///@{
  /**
   * Threads for the walks (default 0: all).
   */
  void SetNumberOfThreads(int threads);
  int GetNumberOfThreads();
  ///@}

  /**
   * Whether the last execution built a boundary (its hierarchy and values)
   * for any of its solves; false when every solve reused the boundary kept
   * from an execution before (the inputs and arrays it is built from
   * unchanged: moved points, other walks or another seed).
   */
  bool GetLastBoundaryBuilt();

protected:
  vtkWalkOnSpheresAlgorithm();
  ~vtkWalkOnSpheresAlgorithm() override;

  // Starts each execution's GetLastBoundaryBuilt afresh.
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // The settings this filter keeps; the subclass's own properties live
  // here too.
  gridfree::SolveSettings& GetSettings();
  const gridfree::SolveSettings& GetSettings() const;

  // The problem of `data` with `settings` and `arrays`, built by the
  // builder the subclass's solve number `problem` keeps (0, 1, ... for
  // solves of different boundary values), reusing its boundary while it
  // is built from the same data. False after an error (reported as this
  // filter's).
  bool BuildKeptProblem(int problem, const gridfree::SolveSettings& settings,
    const gridfree::ArraySelections& arrays, const gridfree::ProblemData& data,
    gridfree::BuiltProblem& built);

  // The builder the subclass's solve number `problem` keeps, for a subclass
  // that resolves and builds in two steps (the solver checks its kept sums
  // in between); it reports what its Build did with NoteBoundaryBuilt.
  gridfree::ProblemBuilder& KeptBuilder(int problem);
  void NoteBoundaryBuilt(bool built);

private:
  vtkWalkOnSpheresAlgorithm(const vtkWalkOnSpheresAlgorithm&) = delete;
  void operator=(const vtkWalkOnSpheresAlgorithm&) = delete;

  struct State;
  std::unique_ptr<State> Kept;
};

#endif
