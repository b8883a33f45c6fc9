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
   * - SPHERE_CACHE: by walks from spheres inside the domain that every
   *   probe shares: a point deeper than CacheShellDistance is answered by
   *   Poisson's integral formula over the nearest sphere of a lattice that
   *   holds it (WalksPerSphere walks, made when a point first needs it and
   *   kept), with no walks of its own; nearby points share a sphere, so
   *   their errors are correlated within it;
   * - BOUNDARY_CACHE: by a boundary value cache (Miller et al. 2023): walks
   *   estimate the normal derivative once, at CachePoints points on the
   *   boundary, and each point is answered by Green's representation
   *   formula; its errors are correlated over the whole probe.
   * Points closer to the boundary than CacheShellDistance take their own
   * walks; points outside the closed boundary get NaN (interior problems
   * only). A cache is kept with the problem: a moved probe (slice, seeds)
   * reuses it; a change of the boundary, its values, the source, the
   * equation, Epsilon, MaxSteps, the seed or the cache's own settings
   * builds a new one. More WalksPerSphere (WalksPerCachePoint) grows the
   * cache; a TargetStandardError grows its walks (per sphere, or per
   * boundary cache point) until every point it answers meets the target,
   * up to WalksPerPoint; a time budget's rounds give it at least a point's
   * walks. Laplace's, Poisson's and the screened Poisson equation (volume
   * sources; the sphere cache also point and curve sources) on a closed
   * mesh, with Dirichlet conditions (the sphere cache also with Neumann and
   * Robin parts); the value and gradient, and with the sphere cache the
   * directional derivative, divergence and curl, and Hessian.
   */
  enum EstimatorType
  {
    POINTWISE_WALKS = 0,
    BOUNDARY_CACHE = 1,
    SPHERE_CACHE = 2
  };
  void SetEstimator(int estimator);
  int GetEstimator();
  ///@}

  ///@{
  /**
   * Points closer to the boundary than this (relative to its bounding-box
   * diagonal; default 0.02) take their own walks rather than the cache's
   * answer (SPHERE_CACHE, BOUNDARY_CACHE).
   */
  void SetCacheShellDistance(double distance);
  double GetCacheShellDistance();
  ///@}

  ///@{
  /**
   * The sphere cache (SPHERE_CACHE): walks per sphere when it is made
   * (default 128), and samples of a source's integral over the sphere per
   * answered point (default 256).
   */
  void SetWalksPerSphere(int walks);
  int GetWalksPerSphere();
  void SetCacheSourceSamples(int samples);
  int GetCacheSourceSamples();
  ///@}

  ///@{
  /**
   * The polynomial control variate (default 0, none): the degree, 1 to 12,
   * of a polynomial P fitted by least squares to the boundary values and
   * the source (P ≈ g on the boundary, ΔP − c·P ≈ f inside). The walks
   * then estimate w = u − P, whose boundary values are g − P and whose
   * source is f − (ΔP − c·P), and P, ∇P and ∇²P are added back: exact
   * whatever P is, and the closer P is to u the fewer walks a target needs
   * (a fifth of a walk's variance on the CT workflow at degree 6). For the Laplace,
   * Poisson and screened Poisson equations with Dirichlet values of one
   * component on a closed mesh, with a volume source (no point or curve
   * sources); points outside the closed boundary are NaN.
   */
  void SetPolynomialControlVariate(int degree);
  int GetPolynomialControlVariate();
  ///@}

  ///@{
  /**
   * The boundary cache (BOUNDARY_CACHE): points on the boundary (default
   * 4096; two per stratum of equal area), walks per cache point (default
   * 64; more grows the cache), points of a source's volume integral
   * (default 8192), and how far inside the boundary the normal derivative
   * is estimated (CacheOffset, relative to the diagonal; default 0.01).
   */
  void SetCachePoints(int points);
  int GetCachePoints();
  void SetWalksPerCachePoint(int walks);
  int GetWalksPerCachePoint();
  void SetCacheVolumePoints(int points);
  int GetCacheVolumePoints();
  void SetCacheOffset(double offset);
  double GetCacheOffset();
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
