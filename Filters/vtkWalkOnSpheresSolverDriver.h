/**
 * @class   vtkWalkOnSpheresSolverDriver
 * @brief   Base of filters that estimate the solution at points they choose
 *          themselves (the stream tracer's integrator points, the adaptive
 *          sampler's samples).
 *
 * Input 0 ("Boundary") and input 2 ("Source", optional) are those of
 * vtkWalkOnSpheresSolver; input 1 is the subclass's own (seeds, candidate
 * points). The boundary array is the one selected on this filter with
 * SetInputArrayToProcess(0, ...) (and 1, 2 for the biharmonic Laplacian and
 * the source array). The problem (boundary, hierarchy, values, sources) is
 * built once per execution and then asked directly for the value and the
 * gradient at each batch of points, with no internal pipeline; the boundary
 * is kept between executions while the Boundary input, the implicit
 * boundary and the boundary settings are unchanged
 * (vtkWalkOnSpheresAlgorithm). Every input is requested whole.
 *
 * @sa vtkWalkOnSpheresAlgorithm vtkWalkOnSpheresStreamTracer vtkWalkOnSpheresAdaptiveSampler
 */
#ifndef vtkWalkOnSpheresSolverDriver_h
#define vtkWalkOnSpheresSolverDriver_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresAlgorithm.h"

#include <array>   // for std::array
#include <functional> // for std::function
#include <memory>  // for std::unique_ptr
#include <vector>  // for std::vector

class vtkAlgorithmOutput;
class vtkDataObject;
class vtkDataSet;
class vtkImplicitFunction;
class vtkPointData;
class vtkPolyData;
namespace gridfree
{
struct EstimateArrays;
struct PointNumbers;
struct PointEstimateRun;
struct PointEstimateSummary;
}

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresSolverDriver : public vtkWalkOnSpheresAlgorithm
{
public:
  vtkTypeMacro(vtkWalkOnSpheresSolverDriver, vtkWalkOnSpheresAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The Boundary (port 0) and Source (port 2) inputs.
   */
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * The equation (vtkWalkOnSpheresSolver::EquationType: Laplace 0, Poisson
   * 1, screened Poisson 2, biharmonic 3, varying coefficients 4; default
   * Laplace) and its screening coefficient c > 0 (default 1).
   */
  void SetEquation(int equation);
  int GetEquation();
  void SetScreeningCoefficient(double c);
  double GetScreeningCoefficient();
  ///@}

  ///@{
  /**
   * The equation with varying coefficients (vtkWalkOnSpheresSolver's
   * properties of the same names): the constant α and σ where input arrays
   * 7 and 8 (point arrays of a vtkImageData Source) give none, the arrays'
   * Gaussian smoothing width, and whether α, σ and f are read from arrays.
   */
  void SetDiffusionCoefficient(double alpha);
  double GetDiffusionCoefficient();
  void SetAbsorptionCoefficient(double sigma);
  double GetAbsorptionCoefficient();
  void SetCoefficientSmoothing(double width);
  double GetCoefficientSmoothing();
  void SetDiffusionFromArray(bool fromArray);
  bool GetDiffusionFromArray();
  void SetAbsorptionFromArray(bool fromArray);
  bool GetAbsorptionFromArray();
  void SetSourceTermFromArray(bool fromArray);
  bool GetSourceTermFromArray();
  void SetDiffusionExpression(const char* expression);
  const char* GetDiffusionExpression();
  void SetAbsorptionExpression(const char* expression);
  const char* GetAbsorptionExpression();
  ///@}

  /**
   * The source term f as an expression in x, y, z (Poisson, screened
   * Poisson and varying coefficients), added to the Source input's.
   */
  void SetSourceExpression(const char* expression);
  const char* GetSourceExpression();

  /**
   * An implicit boundary instead of (or with values from) the Boundary
   * input; see vtkWalkOnSpheresSolver::SetImplicitBoundary.
   */
  void SetImplicitBoundary(vtkImplicitFunction* function);
  vtkImplicitFunction* GetImplicitBoundary();
  ///@{
  /**
   * The rest of the boundary and equation settings, as
   * vtkWalkOnSpheresSolver's properties of the same names: boundary values
   * (and the biharmonic h) as expressions in x, y, z; the implicit
   * function's LipschitzBound; CsgOperation and CsgBlendRadius for a
   * composite Boundary; TwoSidedBoundaryValues (the back side's array is
   * input array 3); MixedBoundaryConditions (the condition, flux and Robin
   * coefficient arrays are input arrays 4, 5 and 6: Neumann and Robin
   * parts, solved by walk on stars with derivatives from a first ball clear
   * of the whole boundary); SourceSampling; BiharmonicStrategy and
   * NestedWalks.
   */
  void SetBoundaryValueExpression(const char* expression);
  const char* GetBoundaryValueExpression();
  void SetBoundaryLaplacianExpression(const char* expression);
  const char* GetBoundaryLaplacianExpression();
  void SetLipschitzBound(double bound);
  double GetLipschitzBound();
  void SetCsgOperation(int operation);
  int GetCsgOperation();
  void SetCsgBlendRadius(double radius);
  double GetCsgBlendRadius();
  void SetTwoSidedBoundaryValues(bool twoSided);
  bool GetTwoSidedBoundaryValues();
  void SetMixedBoundaryConditions(bool mixed);
  bool GetMixedBoundaryConditions();
  vtkBooleanMacro(MixedBoundaryConditions, bool);
  void SetSourceSampling(int sampling);
  int GetSourceSampling();
  /// What the source term is made of the source data: the values, or the
  /// divergence or curl of their vector field (vtkWalkOnSpheresSolver's
  /// SOURCE_VALUE, SOURCE_DIVERGENCE, SOURCE_CURL).
  void SetSourceOperator(int op);
  int GetSourceOperator();
  void SetBiharmonicStrategy(int strategy);
  int GetBiharmonicStrategy();
  void SetNestedWalks(int walks);
  int GetNestedWalks();
  ///@}

  ///@{
  /**
   * The gradient's variance reduction (those of vtkWalkOnSpheresSolver):
   * ControlVariates (default on) and AntitheticPairs (default off). The
   * sampling settings (walks: 128 by default, 1024 for the stream tracer;
   * ε, steps, seed, threads) are vtkWalkOnSpheresAlgorithm's.
   */
  void SetControlVariates(bool on);
  bool GetControlVariates();
  void SetAntitheticPairs(bool on);
  bool GetAntitheticPairs();
  ///@}

  ///@{
  /**
   * Walks from near the boundary split in two as they go deep (default
   * on; vtkWalkOnSpheresSolver::SetNearBoundarySplitting).
   */
  void SetNearBoundarySplitting(bool on);
  bool GetNearBoundarySplitting();
  ///@}

  ///@{
  /**
   * The output: the lines or samples (vtkPolyData).
   */
  vtkPolyData* GetOutput();
  vtkPolyData* GetOutput(int port);
  ///@}

  /**
   * Includes the implicit boundary's MTime.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkWalkOnSpheresSolverDriver();
  ~vtkWalkOnSpheresSolverDriver() override;

  static constexpr int BoundaryPort = 0;
  static constexpr int SourcePort = 2;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  // The output is a vtkPolyData whatever the Boundary's type.
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Builds the problem of the Boundary and Source inputs and this filter's
  // array selections and settings (reusing the kept boundary when it can);
  // an implicit boundary lives around `region`. False after an error.
  bool BuildProblem(vtkDataObject* boundary, vtkDataObject* source, vtkDataSet* region);

  // Estimates the value and gradient at `points` with the built problem
  // and adds the arrays (named as vtkWalkOnSpheresSolver's output) to
  // `arrays`; progress stays at `progress`. Walks and seconds are added to
  // `walks` and `seconds`; `found`, when given, holds the arrays too, to be
  // read by member. False when aborted, or when the batch failed
  // (reported as this filter's error; GetEstimateFailed() tells, and
  // `arrays` may then lack the solution arrays).
  bool EstimateAt(const std::vector<std::array<double, 3>>& points, vtkPointData* arrays,
    double progress, double& seconds, vtkIdType& walks,
    gridfree::EstimateArrays* found = nullptr);
  // The same batch for a subclass that uses the numbers itself: the core's
  // collected estimates (GridFreePointNumbers.h); nothing goes to an output.
  bool EstimateNumbersAt(const std::vector<std::array<double, 3>>& points,
    gridfree::PointNumbers& estimates, double progress, double& seconds, vtkIdType& walks);
  // Whether a batch of this execution failed (BuildProblem resets it).
  bool GetEstimateFailed();

  // The name of the solution arrays of the built problem, and its components.
  const char* GetSolutionName();
  int GetSolutionComponents();

  // Reports each distinct warning of the estimates once, as this filter's.
  void ReportWarnings();

private:
  vtkWalkOnSpheresSolverDriver(const vtkWalkOnSpheresSolverDriver&) = delete;
  bool RunBatch(const std::function<bool(const gridfree::PointEstimateRun&,
                  gridfree::PointEstimateSummary&)>& estimate,
    double progress, double& seconds, vtkIdType& walks);
  void operator=(const vtkWalkOnSpheresSolverDriver&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
