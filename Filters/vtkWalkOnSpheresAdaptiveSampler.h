/**
 * @class   vtkWalkOnSpheresAdaptiveSampler
 * @brief   Places walk-on-spheres samples where the solution needs them
 *          (paper Sec. 5.2.2, irradiance-gradient style) and outputs the
 *          sample cloud with value, gradient and variances.
 *
 * Input 0 ("Boundary") and input 2 ("Source", optional) are the solver's
 * (see vtkWalkOnSpheresSolver); input 1 ("Domain") is any vtkDataSet whose
 * points are the candidate sample locations: the pixels of a slice or an
 * image, a point cloud. The problem is built once per execution and asked
 * directly for value and gradient at the chosen points (settings: see
 * vtkWalkOnSpheresSolverDriver); the boundary array is the one selected on
 * this filter with SetInputArrayToProcess(0, ...). An implicit boundary is
 * built around the Domain's points.
 *
 * 1. About InitialSamples well-spread candidates are solved first (the
 *    candidate nearest the centre of each occupied cell of a uniform grid).
 * 2. At every candidate not yet sampled, the NumberOfNeighbors nearest
 *    samples it sees (segments not crossing the boundary, when UseVisibility
 *    is on and the boundary is a mesh) predict the value by their first-order
 *    Taylor expansions u_i + ∇u_i·(x − y_i). Where the predictions' sample
 *    variance, less the part their Monte Carlo noise explains, exceeds
 *    (Threshold × scale)², the candidate needs a sample; the scale is the
 *    range of the first samples' values when ThresholdIsRelative (default),
 *    else 1 (Threshold in the solution's units). Several components: the
 *    largest component's excess counts.
 * 3. Candidates needing a sample are taken in decreasing excess, skipping
 *    those closer to an already taken one than half their distance to the
 *    nearest sample (so a round does not pile samples on one spot), at most
 *    as many as there are samples (the set at most doubles per round), and
 *    solved. Rounds repeat until no candidate needs a sample, MaximumSamples
 *    is reached or MaximumRounds have run.
 *
 * The output is a vtkPolyData with one vertex per sample carrying the
 * solver's arrays (`T`, `T_Variance`, `T_Gradient`, `T_Gradient_Variance`,
 * `WalkSteps`...) plus `RefinementRound` (0 for the first samples),
 * `DomainPointId` (the candidate's id in the Domain) and
 * `TaylorDisagreement` (the excess that called for the sample, in units of
 * (Threshold × scale)²; NaN for the first samples). Field data `TotalWalks`,
 * `SolveSeconds` (the solver's time), `SamplingSeconds` (everything), and
 * `RefinementRounds`. Interpolate the cloud onto the domain with
 * vtkMovingLeastSquaresInterpolator.
 *
 * A sample's value is the one the solver gives at that point on its own
 * (walks depend on the seed, the point and the walk's number only), and the
 * choice of samples depends on no thread count: the output is reproducible.
 *
 * @sa vtkMovingLeastSquaresInterpolator vtkWalkOnSpheresSolver
 */
#ifndef vtkWalkOnSpheresAdaptiveSampler_h
#define vtkWalkOnSpheresAdaptiveSampler_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresSolverDriver.h"

class vtkAlgorithmOutput;
class vtkDataObject;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresAdaptiveSampler : public vtkWalkOnSpheresSolverDriver
{
public:
  static vtkWalkOnSpheresAdaptiveSampler* New();
  vtkTypeMacro(vtkWalkOnSpheresAdaptiveSampler, vtkWalkOnSpheresSolverDriver);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The candidate points (port 1). Boundary (port 0) and Source (port 2):
   * see vtkWalkOnSpheresSolverDriver, which also holds the solve's
   * settings.
   */
  void SetDomainConnection(vtkAlgorithmOutput* output);
  void SetDomainData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Samples of the first round (default 256) and in all (default 4096).
   */
  vtkSetClampMacro(InitialSamples, int, 1, VTK_INT_MAX);
  vtkGetMacro(InitialSamples, int);
  vtkSetClampMacro(MaximumSamples, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumSamples, int);
  ///@}

  ///@{
  /**
   * σ of the refinement test (default 0.01), relative to the range of the
   * first samples' values (default) or in the solution's units.
   */
  vtkSetClampMacro(Threshold, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Threshold, double);
  vtkSetMacro(ThresholdIsRelative, bool);
  vtkGetMacro(ThresholdIsRelative, bool);
  vtkBooleanMacro(ThresholdIsRelative, bool);
  ///@}

  ///@{
  /**
   * Samples whose predictions are compared at a candidate (default 8).
   */
  vtkSetClampMacro(NumberOfNeighbors, int, 2, 256);
  vtkGetMacro(NumberOfNeighbors, int);
  ///@}

  ///@{
  /**
   * Refinement rounds at most (default 16).
   */
  vtkSetClampMacro(MaximumRounds, int, 0, VTK_INT_MAX);
  vtkGetMacro(MaximumRounds, int);
  ///@}

  ///@{
  /**
   * Compare only samples visible from the candidate (default on; mesh
   * boundaries only, an implicit boundary blocks nothing).
   */
  vtkSetMacro(UseVisibility, bool);
  vtkGetMacro(UseVisibility, bool);
  vtkBooleanMacro(UseVisibility, bool);
  ///@}

  ///@{
  /**
   * Summary of the last execution: walks run (value and gradient walks),
   * samples, rounds, and seconds (all of it).
   */
  vtkGetMacro(LastNumberOfWalks, vtkIdType);
  vtkGetMacro(LastNumberOfSamples, vtkIdType);
  vtkGetMacro(LastNumberOfRounds, int);
  vtkGetMacro(LastSeconds, double);
  ///@}

protected:
  vtkWalkOnSpheresAdaptiveSampler();
  ~vtkWalkOnSpheresAdaptiveSampler() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int InitialSamples = 256;
  int MaximumSamples = 4096;
  double Threshold = 0.01;
  bool ThresholdIsRelative = true;
  int NumberOfNeighbors = 8;
  int MaximumRounds = 16;
  bool UseVisibility = true;
  vtkIdType LastNumberOfWalks = 0;
  vtkIdType LastNumberOfSamples = 0;
  int LastNumberOfRounds = 0;
  double LastSeconds = 0.0;

private:
  vtkWalkOnSpheresAdaptiveSampler(const vtkWalkOnSpheresAdaptiveSampler&) = delete;
  void operator=(const vtkWalkOnSpheresAdaptiveSampler&) = delete;
};

#endif
