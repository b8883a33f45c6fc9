/**
 * @class   vtkSignedDistanceSphere
 * @brief   exact signed distance to a sphere: |x − Center| − Radius
 *
 * Negative inside the ball, with the unit gradient (x − Center)/|x − Center|
 * (any unit vector at the center). Unlike vtkSphere (|x − c|² − r², whose
 * slope grows with the distance), its Lipschitz constant is 1, so walk on
 * spheres takes the largest safe steps. Radius must be positive and finite;
 * otherwise the function is NaN (see vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive vtkSphere
 */
#ifndef vtkSignedDistanceSphere_h
#define vtkSignedDistanceSphere_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceSphere : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceSphere* New();
  vtkTypeMacro(vtkSignedDistanceSphere, vtkSignedDistancePrimitive);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The signed distance and its gradient at x (in the function's own
   * coordinates; FunctionValue applies the Transform first).
   */
  using vtkImplicitFunction::EvaluateFunction;
  double EvaluateFunction(double x[3]) override;
  void EvaluateGradient(double x[3], double g[3]) override;
  ///@}

  ///@{
  /**
   * The center (default 0, 0, 0).
   */
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /**
   * The radius (default 0.5; must be positive).
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

protected:
  vtkSignedDistanceSphere();
  ~vtkSignedDistanceSphere() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double Radius = 0.5;

private:
  vtkSignedDistanceSphere(const vtkSignedDistanceSphere&) = delete;
  void operator=(const vtkSignedDistanceSphere&) = delete;
};

#endif
