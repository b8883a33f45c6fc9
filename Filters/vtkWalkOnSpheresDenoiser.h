/**
 * @class   vtkWalkOnSpheresDenoiser
 * @brief   Edge-aware denoising of walk-on-spheres estimates, guided by their
 *          variance and by the boundary value at the closest boundary point
 *          (paper Sec. 5.2.4).
 *
 * A walk-on-spheres solution is a Monte Carlo image: every point carries an
 * independent estimate and its variance, like a rendered pixel. This filter
 * replaces each estimate by a weighted mean of itself and its neighbours
 * within 2.5 SpatialSigma, with weights that are the product of
 * - a spatial Gaussian of standard deviation SpatialSigma;
 * - a Gaussian in the guide, the "albedo" of the paper: the boundary value at
 *   the closest boundary point, which vtkWalkOnSpheresSolver outputs and
 *   which jumps where the solution has its sharpest features, so averaging
 *   stops there (standard deviation GuideSigma);
 * - a range term that compares the two estimates in units of their noise
 *   (Rousselle, Knaus & Zwicker 2012): neighbours whose difference the noise
 *   explains are averaged, a difference of about VarianceScale noise sigmas
 *   or more is not. The formula is in Core/JointBilateralDenoising.h.
 *
 * The input is any vtkDataSet with point data; only its points matter (an
 * image, a slice from vtkPlaneSource or a point cloud), neighbours are found
 * by distance. The arrays are chosen with SetInputArrayToProcess:
 * - index 0: the values (point data, any number of components; default: the
 *   active point scalars), say `T`;
 * - index 1: their variance, one per component (default: the point array
 *   `T_Variance`); without it the filter reports an error;
 * - index 2: the guide (default: the point array `T_ClosestBoundaryValue`);
 *   without it, or with UseGuide off, the guide term is left out (with a
 *   warning when UseGuide is on).
 *
 * The output has the input's type, structure and arrays, with
 * - `T`: the denoised values (active scalars if `T` was);
 * - `T_Variance`: their variance, Σ w² v / (Σ w)², which counts the noise
 *   left but not the bias the averaging adds;
 * - `T_Noisy`, `T_Noisy_Variance`: the input's values and variances;
 * and field data `DenoiseSeconds`. A point whose value or variance is NaN,
 * infinite or negative keeps its input and is nobody's neighbour.
 *
 * The range term compares single points, so it is as noisy as they are: the
 * default VarianceScale of 2 removes about 3.4 times the error on 16-walk
 * slices (1 gives 2 times), at the price of smoothing value jumps the guide
 * does not show unless they reach about 5 noise sigmas.
 *
 * Every point is computed on its own from its neighbours in a fixed order:
 * the output is the same for any NumberOfThreads. Pieces of a distributed
 * dataset are denoised separately (points of other pieces are not
 * neighbours unless present as ghosts).
 *
 * @sa vtkWalkOnSpheresSolver
 */
#ifndef vtkWalkOnSpheresDenoiser_h
#define vtkWalkOnSpheresDenoiser_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

#include <string> // for std::string

class vtkDataArray;
class vtkDataSet;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresDenoiser : public vtkDataSetAlgorithm
{
public:
  static vtkWalkOnSpheresDenoiser* New();
  vtkTypeMacro(vtkWalkOnSpheresDenoiser, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Standard deviation of the spatial Gaussian (default 2). With
   * SpatialSigmaIsRelative on (the default) it is in units of the typical
   * point spacing, the median distance from a point to its nearest
   * neighbour (measured on up to 1000 points); otherwise in world units.
   * Neighbours are searched within 2.5 SpatialSigma, so the cost grows like
   * SpatialSigma² on a slice and SpatialSigma³ in a volume.
   */
  vtkSetClampMacro(SpatialSigma, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(SpatialSigma, double);
  vtkSetMacro(SpatialSigmaIsRelative, bool);
  vtkGetMacro(SpatialSigmaIsRelative, bool);
  vtkBooleanMacro(SpatialSigmaIsRelative, bool);
  ///@}

  ///@{
  /**
   * k of the range term (default 2): how many noise sigmas a difference
   * between two estimates must reach to stop their averaging. Larger smooths
   * more; 0 averages only equal values.
   */
  vtkSetClampMacro(VarianceScale, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(VarianceScale, double);
  ///@}

  ///@{
  /**
   * Standard deviation of the guide term (default 0.05). With
   * GuideSigmaIsRelative on (the default) it is a fraction of the guide
   * array's range (the largest over its components); otherwise in the
   * guide's units. 0 leaves the guide term out.
   */
  vtkSetClampMacro(GuideSigma, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(GuideSigma, double);
  vtkSetMacro(GuideSigmaIsRelative, bool);
  vtkGetMacro(GuideSigmaIsRelative, bool);
  vtkBooleanMacro(GuideSigmaIsRelative, bool);
  ///@}

  ///@{
  /**
   * Use the guide array (default on). Off, the filter is guided by the
   * variance alone and does not look for a guide.
   */
  vtkSetMacro(UseGuide, bool);
  vtkGetMacro(UseGuide, bool);
  vtkBooleanMacro(UseGuide, bool);
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
   * What the last execution used: the spatial and guide standard deviations
   * in world and guide units (the guide's 0 when it was left out), and its
   * wall-clock seconds.
   */
  vtkGetMacro(LastSpatialSigma, double);
  vtkGetMacro(LastGuideSigma, double);
  vtkGetMacro(LastDenoiseSeconds, double);
  ///@}

protected:
  vtkWalkOnSpheresDenoiser();
  ~vtkWalkOnSpheresDenoiser() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // The numeric point array selected as input array `index` or, without a
  // selection, the point array named `fallback` (the active point scalars
  // when `fallback` is empty). Null, with `problem` saying why, otherwise.
  vtkDataArray* FindPointArray(
    int index, vtkDataSet* input, const std::string& fallback, std::string& problem);

  double SpatialSigma = 2.0;
  bool SpatialSigmaIsRelative = true;
  double VarianceScale = 2.0;
  double GuideSigma = 0.05;
  bool GuideSigmaIsRelative = true;
  bool UseGuide = true;
  int NumberOfThreads = 0;

  double LastSpatialSigma = 0.0;
  double LastGuideSigma = 0.0;
  double LastDenoiseSeconds = 0.0;

private:
  vtkWalkOnSpheresDenoiser(const vtkWalkOnSpheresDenoiser&) = delete;
  void operator=(const vtkWalkOnSpheresDenoiser&) = delete;
};

#endif
