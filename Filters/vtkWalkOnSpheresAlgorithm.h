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

  ///@{
  /**
   * How probe points are answered (default POINTWISE_WALKS):
   * - POINTWISE_WALKS: each point by its own walks;
   * - BOUNDARY_CACHE: by a boundary value cache that every probe shares
   *   (Miller et al. 2023): walks estimate the normal derivative once, at
   *   CachePoints points on the boundary, and each probe point is answered
   *   by Green's representation formula with no walks of its own. Points
   *   closer to the boundary than CacheShellDistance take their own walks;
   *   points outside the closed boundary get NaN (interior problems only).
   *   The cache is kept with the problem: a moved probe (slice, seeds)
   *   reuses it with no new walks; a change of the boundary, its values,
   *   the source, the equation, Epsilon, MaxSteps, the seed or the cache's
   *   settings builds a new one. More WalksPerCachePoint grows it. A
   *   TargetStandardError doubles its walks until every point it answers
   *   meets the target (up to WalksPerPoint walks per cache point).
   *   Laplace, Poisson (volume sources) and screened Poisson equations
   *   with Dirichlet conditions on a closed mesh; value and gradient only.
   *   Nearby points share the cache's walks, so their errors are
   *   correlated: a smooth picture whose error does not average out.
   */
  enum EstimatorType
  {
    POINTWISE_WALKS = 0,
    BOUNDARY_CACHE = 1
  };
  void SetEstimator(int estimator);
  int GetEstimator();
  ///@}

  ///@{
  /**
   * The boundary cache's size (BOUNDARY_CACHE): points on the boundary
   * (default 4096; two per stratum of equal area), walks per cache point
   * (default 64), and points of a source's volume integral (default 8192).
   */
  void SetCachePoints(int points);
  int GetCachePoints();
  void SetWalksPerCachePoint(int walks);
  int GetWalksPerCachePoint();
  void SetCacheVolumePoints(int points);
  int GetCacheVolumePoints();
  ///@}

  ///@{
  /**
   * The boundary cache's depth and shell (BOUNDARY_CACHE), relative to the
   * boundary's bounding-box diagonal: the normal derivative is estimated
   * CacheOffset inside the boundary (default 0.01; smaller is less biased
   * and noisier), and points closer than CacheShellDistance (default 0.05)
   * take their own walks.
   */
  void SetCacheOffset(double offset);
  double GetCacheOffset();
  void SetCacheShellDistance(double distance);
  double GetCacheShellDistance();
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
