/**
 * @class   vtkSignedDistanceCylinder
 * @brief   exact signed distance to a capped cylinder
 *
 * The solid cylinder of radius Radius around Axis through Center, cut at
 * HalfHeight on either side of Center along the axis (flat caps). Exact
 * inside and outside, rim edges included (Lipschitz constant 1), and
 * bounded, unlike vtkCylinder (ρ² − r², infinite). Axis need not be unit
 * length but must not be zero; Radius and HalfHeight must be positive.
 * Otherwise the function is NaN (see vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive vtkSignedDistanceCapsule vtkCylinder
 */
#ifndef vtkSignedDistanceCylinder_h
#define vtkSignedDistanceCylinder_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceCylinder : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceCylinder* New();
  vtkTypeMacro(vtkSignedDistanceCylinder, vtkSignedDistancePrimitive);
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
   * The center of the cylinder, halfway between the caps (default 0, 0, 0).
   */
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /**
   * The direction of the axis (default 0, 0, 1; normalized when evaluated;
   * must not be zero).
   */
  vtkSetVector3Macro(Axis, double);
  vtkGetVector3Macro(Axis, double);
  ///@}

  ///@{
  /**
   * The radius (default 0.5; must be positive).
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /**
   * Half the length along the axis, from Center to either cap (default 0.5;
   * must be positive).
   */
  vtkSetMacro(HalfHeight, double);
  vtkGetMacro(HalfHeight, double);
  ///@}

protected:
  vtkSignedDistanceCylinder();
  ~vtkSignedDistanceCylinder() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double Axis[3] = { 0.0, 0.0, 1.0 };
  double Radius = 0.5;
  double HalfHeight = 0.5;

private:
  vtkSignedDistanceCylinder(const vtkSignedDistanceCylinder&) = delete;
  void operator=(const vtkSignedDistanceCylinder&) = delete;
};

#endif
