/**
 * @class   vtkMovingLeastSquaresInterpolator
 * @brief   Interpolates scattered walk-on-spheres samples onto any dataset
 *          by moving least squares, neighbours limited to those visible
 *          across the boundary (paper Sec. 5.2.1).
 *
 * Input 0 is the target: any vtkDataSet (a slice, an image, points); the
 * output has its type, structure and arrays. Input 1 ("Source") holds the
 * samples: any vtkDataSet whose points carry the value array selected with
 * SetInputArrayToProcess(0, ...) (for example the output of
 * vtkWalkOnSpheresAdaptiveSampler or of vtkWalkOnSpheresSolver on a point
 * cloud), and, when present, `<value>_Gradient`, `<value>_Variance` and
 * `<value>_Gradient_Variance` as the solver names them. Input 2 ("Boundary",
 * optional) is a surface (or, in 2D, lines in one z-plane): a sample is a
 * neighbour of a target point only if the segment between them crosses no
 * boundary primitive, so values never bleed across a thin wall.
 *
 * At every target point a polynomial of degree PolynomialDegree in the offset
 * is fitted to the NumberOfNeighbors nearest visible samples by weighted least
 * squares (Wendland weights over 1.5 times the farthest neighbour's distance),
 * using the samples' gradients as extra equations when UseGradients is on
 * and they exist (Hermite data: a quadratic then follows the solution's
 * curvature from few samples). The output arrays are `<value>` (active
 * scalars), `<value>_Gradient` (3 per component, the fit's gradient),
 * `<value>_Variance` (the Monte Carlo variance the samples' noise gives the
 * fit, Σ r_j² Var(data_j); the interpolation bias is not part of it; only
 * when the samples have variances) and `MLSNeighbors` (visible neighbours
 * used). A point with no visible sample gets NaN, with a warning. Field data
 * `InterpolationSeconds`.
 *
 * @sa vtkWalkOnSpheresAdaptiveSampler vtkWalkOnSpheresSolver vtkPointInterpolator
 */
#ifndef vtkMovingLeastSquaresInterpolator_h
#define vtkMovingLeastSquaresInterpolator_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

class vtkAlgorithmOutput;
class vtkDataObject;

class GRIDFREEFILTERS_EXPORT vtkMovingLeastSquaresInterpolator : public vtkDataSetAlgorithm
{
public:
  static vtkMovingLeastSquaresInterpolator* New();
  vtkTypeMacro(vtkMovingLeastSquaresInterpolator, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The samples (port 1) and the boundary that blocks visibility (port 2,
   * optional). The target is input 0 (SetInputConnection / SetInputData).
   */
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkDataObject* data);
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Visible samples fitted at each point (default 12).
   */
  vtkSetClampMacro(NumberOfNeighbors, int, 1, 1024);
  vtkGetMacro(NumberOfNeighbors, int);
  ///@}

  ///@{
  /**
   * Degree of the local polynomial: 0 (a weighted average), 1 or 2 (default).
   */
  vtkSetClampMacro(PolynomialDegree, int, 0, 2);
  vtkGetMacro(PolynomialDegree, int);
  ///@}

  ///@{
  /**
   * Fit the samples' gradients as well as their values (default on; used
   * only when the `<value>_Gradient` array exists and the degree is 1 or 2).
   */
  vtkSetMacro(UseGradients, bool);
  vtkGetMacro(UseGradients, bool);
  vtkBooleanMacro(UseGradients, bool);
  ///@}

  ///@{
  /**
   * Weight of a gradient equation relative to a value equation (default 1).
   */
  vtkSetClampMacro(GradientWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(GradientWeight, double);
  ///@}

  ///@{
  /**
   * Exclude samples hidden by the boundary (default on; needs the Boundary
   * input, without it every sample is visible).
   */
  vtkSetMacro(UseVisibility, bool);
  vtkGetMacro(UseVisibility, bool);
  vtkBooleanMacro(UseVisibility, bool);
  ///@}

  ///@{
  /**
   * Threads (0, the default: all).
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  /**
   * Target points without any visible sample in the last execution.
   */
  vtkGetMacro(LastNumberOfUnreachedPoints, vtkIdType);

protected:
  vtkMovingLeastSquaresInterpolator();
  ~vtkMovingLeastSquaresInterpolator() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int NumberOfNeighbors = 12;
  int PolynomialDegree = 2;
  bool UseGradients = true;
  double GradientWeight = 1.0;
  bool UseVisibility = true;
  int NumberOfThreads = 0;
  vtkIdType LastNumberOfUnreachedPoints = 0;

private:
  vtkMovingLeastSquaresInterpolator(const vtkMovingLeastSquaresInterpolator&) = delete;
  void operator=(const vtkMovingLeastSquaresInterpolator&) = delete;
};

#endif
