/**
 * @class   vtkWalkOnSpheresDiffusionCurves
 * @brief   Diffusion curves (2D) and diffusion surfaces (3D): colours given
 *          on the two sides of curves or surfaces, spread smoothly over the
 *          plane or space by walk on spheres (paper Sec. 6.4, Figs. 16, 18).
 *
 * The colour u solves the Laplace equation Δu = 0, or the Poisson equation
 * Δu = f when a source is given, with two-sided boundary values: every
 * boundary point has a front colour and a back colour, and a walk takes the
 * colour of the side it ends on (vtkWalkOnSpheresSolver's
 * TwoSidedBoundaryValues). The front is the side the boundary's oriented
 * normal points to: the left of a line or Bézier curve, in the direction
 * of its points; the side from which a polygon's points turn
 * counter-clockwise (the outside of an outward-wound closed surface).
 * Curves need not be closed: an open curve divides nothing, its two sides
 * simply carry different colours, as in Orzan et al. 2008.
 *
 * Input port 0, "Boundary": polylines in one z-plane (2D; polylines marked
 * by the cell array BezierControlPoints = 1 are piecewise cubic Bézier
 * curves, see vtkWalkOnSpheresSolver) or a surface (3D), with the front
 * colours as input array 0 (default: the point array "FrontColor") and the
 * back colours as input array 1 (default "BackColor"), point or cell data,
 * any number of components (3 for RGB), the same for both.
 *
 * Input port 1, "Probe", optional: where to evaluate the colours, any
 * dataset (a slice plane through a surface, points, an image); the output
 * has its type and arrays. Without a probe, a 2D problem makes its own
 * image: ImageResolution pixels over ImageWindow of the boundary's plane.
 * The image honours the update extent, so a piece (or a zoomed window)
 * costs only its own pixels: Monte Carlo needs no global solve to zoom in.
 * A 3D problem needs a probe.
 *
 * Input port 2, "Source", optional: the source term f of Δu = f, as for
 * vtkWalkOnSpheresSolver (an image or dataset with a point array, input
 * array 2; or point and curve sources as vertices and lines with a strength
 * per point); SourceExpression adds f in closed form. Note the sign: a
 * negative f raises u (it is a source of colour), a positive one lowers it.
 * A one-component source applies to every colour component.
 *
 * Output: the probe (or the image) with, for front array F,
 * - `F`: the colour, `F_Variance`: the variance of its Monte Carlo mean;
 * - for 1 or 3 components, `F_RGB`: unsigned char colours (grey for one
 *   component), ColorRange mapped to 0–255 and clamped, ready to show
 *   without a colour map (ParaView: Map Scalars off);
 * - the solver's walk statistics (WalkSteps, EscapedFraction,
 *   TruncatedFraction) and field data TotalWalks and SolveSeconds.
 * Probe points outside a closed boundary (and every point around open
 * curves) solve the exterior problem (bounded in 2D, → 0 at infinity in 3D).
 *
 * @sa vtkWalkOnSpheresSolver vtkWalkOnSpheresProbeAlgorithm
 */
#ifndef vtkWalkOnSpheresDiffusionCurves_h
#define vtkWalkOnSpheresDiffusionCurves_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresProbeAlgorithm.h"

class vtkAlgorithmOutput;
class vtkDataObject;
class vtkImageData;
class vtkPolyData;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresDiffusionCurves : public vtkWalkOnSpheresProbeAlgorithm
{
public:
  static vtkWalkOnSpheresDiffusionCurves* New();
  vtkTypeMacro(vtkWalkOnSpheresDiffusionCurves, vtkWalkOnSpheresProbeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The source term's dataset (port 2).
   */
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * The source term f(x, y, z) of Δu = f in closed form (default none), in
   * the syntax of vtkWalkOnSpheresSolver::SourceExpression; a vector
   * (iHat, jHat, kHat) gives one source per colour component.
   */
  virtual void SetSourceExpression(const char* expression); // null clears it
  const char* GetSourceExpression();
  ///@}

  ///@{
  /**
   * The window of the plane the image covers when there is no Probe
   * (xmin, xmax, ymin, ymax; default all 0: the boundary's bounds, enlarged
   * by 5% on each side). Pixel (i, j) is at xmin + i·(xmax − xmin)/(nx − 1),
   * ymin + j·(ymax − ymin)/(ny − 1).
   */
  vtkSetVector4Macro(ImageWindow, double);
  vtkGetVector4Macro(ImageWindow, double);
  ///@}

  ///@{
  /**
   * Pixels of that image along x and y (default 256 × 256, at least 2).
   */
  vtkSetVector2Macro(ImageResolution, int);
  vtkGetVector2Macro(ImageResolution, int);
  ///@}

  ///@{
  /**
   * The colour values shown as 0 and 255 in the `_RGB` array (default
   * 0 and 1).
   */
  vtkSetVector2Macro(ColorRange, double);
  vtkGetVector2Macro(ColorRange, double);
  ///@}

protected:
  vtkWalkOnSpheresDiffusionCurves();
  ~vtkWalkOnSpheresDiffusionCurves() override;

  static constexpr int SourcePort = 2;

  // The probe is optional.
  int FillInputPortInformation(int port, vtkInformation* info) override;
  // Without a probe, the output is an image of ImageResolution pixels.
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ImageWindow[4] = { 0.0, 0.0, 0.0, 0.0 };
  int ImageResolution[2] = { 256, 256 };
  double ColorRange[2] = { 0.0, 1.0 };

private:
  vtkWalkOnSpheresDiffusionCurves(const vtkWalkOnSpheresDiffusionCurves&) = delete;
  void operator=(const vtkWalkOnSpheresDiffusionCurves&) = delete;

  // The image of the update extent `extent` over the window, in the
  // boundary's plane; false with an error when the window is empty.
  bool MakeImage(vtkPolyData* boundary, const int extent[6], vtkImageData* image);
};

#endif
