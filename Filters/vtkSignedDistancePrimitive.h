/**
 * @class   vtkSignedDistancePrimitive
 * @brief   abstract base of exact signed distance functions of simple solids
 *
 * The subclasses (vtkSignedDistanceSphere, vtkSignedDistanceBox,
 * vtkSignedDistanceRoundedBox, vtkSignedDistanceTorus,
 * vtkSignedDistanceCylinder, vtkSignedDistanceCapsule,
 * vtkSignedDistancePlane) evaluate the true signed Euclidean distance to
 * their surface: negative inside, zero on the surface, positive outside, with
 * an analytic gradient of unit length. They compute exactly the numbers of the
 * estimator core's functions, so vtkWalkOnSpheresSolver can use them, and
 * vtkImplicitBoolean unions, intersections and differences of them, without
 * calling back into VTK (see vtkWalkOnSpheresSolver::SetImplicitBoundary).
 * They are ordinary vtkImplicitFunctions too: clip, cut or contour with them.
 *
 * Lipschitz constant: a signed distance changes at most as fast as the point
 * moves, so its Lipschitz constant is 1, and so is that of min/max
 * combinations of such functions. vtkImplicitFunction evaluates
 * φ(T(x)) when a Transform T is set; a rigid motion keeps the constant 1,
 * any other linear transform multiplies it by the largest singular value of
 * its matrix (GetLipschitzConstant() returns that), and a non-linear one
 * makes it unknown.
 *
 * Invalid parameters (a radius <= 0, a zero axis, non-finite numbers, ...)
 * never throw and never crash: EvaluateFunction returns NaN and
 * EvaluateGradient NaN components, GetParameterError() says what is wrong,
 * and vtkWalkOnSpheresSolver refuses such a function with an error.
 *
 * @sa vtkImplicitFunction vtkImplicitBoolean vtkWalkOnSpheresSolver
 */
#ifndef vtkSignedDistancePrimitive_h
#define vtkSignedDistancePrimitive_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkImplicitFunction.h"

#include <string> // for std::string

class vtkAbstractTransform;

class GRIDFREEFILTERS_EXPORT vtkSignedDistancePrimitive : public vtkImplicitFunction
{
public:
  vtkTypeMacro(vtkSignedDistancePrimitive, vtkImplicitFunction);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The axis-aligned box (xmin, xmax, ymin, ymax, zmin, zmax) that holds the
   * zero set, in world coordinates: without a Transform the tight box of the
   * solid; with a linear Transform the box of the transformed tight box.
   * Returns false (bounds untouched) when the zero set is unbounded (a
   * plane), the parameters are invalid, or the Transform is not linear or
   * not invertible.
   */
  virtual bool GetZeroSetBounds(double bounds[6]);

  /**
   * A Lipschitz constant of FunctionValue(): 1 without a Transform (an exact
   * distance), the largest singular value of the matrix of a linear
   * Transform (1 again for rigid motions), 0 when it is not known (a
   * non-linear Transform).
   */
  double GetLipschitzConstant();

  /**
   * The factor by which `transform` can multiply the slope of a function it
   * is applied to: 1 for none, the largest singular value of a linear
   * transform's 3x3 matrix, 0 when unknown (non-linear transforms).
   */
  static double TransformLipschitzFactor(vtkAbstractTransform* transform);

  /**
   * Empty when the parameters define a solid; otherwise a sentence naming
   * the class and the offending parameter. EvaluateFunction returns NaN
   * while it is not empty.
   */
  std::string GetParameterError();

  /**
   * True when GetParameterError() is empty.
   */
  bool HasValidParameters();

protected:
  vtkSignedDistancePrimitive();
  ~vtkSignedDistancePrimitive() override;

  /**
   * nullptr when the parameters are valid, else a static description of
   * what is wrong. Cheap: EvaluateFunction calls it at every point.
   */
  virtual const char* GetParameterProblem() = 0;

  /**
   * The tight box of the zero set in the function's own coordinates (before
   * the Transform); false when unbounded. Called with valid parameters only.
   */
  virtual bool GetLocalZeroSetBounds(double bounds[6]) = 0;

private:
  vtkSignedDistancePrimitive(const vtkSignedDistancePrimitive&) = delete;
  void operator=(const vtkSignedDistancePrimitive&) = delete;
};

#endif
