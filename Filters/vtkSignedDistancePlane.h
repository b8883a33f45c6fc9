/**
 * @class   vtkSignedDistancePlane
 * @brief   exact signed distance to a plane: (x − Origin)·n / |n|
 *
 * The half-space on the side opposite to Normal is inside (negative). It is
 * unbounded, so GetZeroSetBounds() returns false; alone it makes a boundary
 * with no enclosed region, so use it to cut other solids in a
 * vtkImplicitBoolean intersection or difference. Lipschitz constant 1,
 * unlike vtkPlane with a non-unit normal. Normal need not be unit length but
 * must not be zero; otherwise the function is NaN (see
 * vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive vtkPlane
 */
#ifndef vtkSignedDistancePlane_h
#define vtkSignedDistancePlane_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistancePlane : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistancePlane* New();
  vtkTypeMacro(vtkSignedDistancePlane, vtkSignedDistancePrimitive);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The signed distance and its gradient (the unit normal) at x (in the
   * function's own coordinates; FunctionValue applies the Transform first).
   */
  using vtkImplicitFunction::EvaluateFunction;
  double EvaluateFunction(double x[3]) override;
  void EvaluateGradient(double x[3], double g[3]) override;
  ///@}

  ///@{
  /**
   * A point of the plane (default 0, 0, 0).
   */
  vtkSetVector3Macro(Origin, double);
  vtkGetVector3Macro(Origin, double);
  ///@}

  ///@{
  /**
   * The normal, pointing outside (default 0, 0, 1; normalized when
   * evaluated; must not be zero).
   */
  vtkSetVector3Macro(Normal, double);
  vtkGetVector3Macro(Normal, double);
  ///@}

protected:
  vtkSignedDistancePlane();
  ~vtkSignedDistancePlane() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Origin[3] = { 0.0, 0.0, 0.0 };
  double Normal[3] = { 0.0, 0.0, 1.0 };

private:
  vtkSignedDistancePlane(const vtkSignedDistancePlane&) = delete;
  void operator=(const vtkSignedDistancePlane&) = delete;
};

#endif
