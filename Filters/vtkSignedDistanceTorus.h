/**
 * @class   vtkSignedDistanceTorus
 * @brief   exact signed distance to a torus
 *
 * The circle of radius MajorRadius around Axis through Center, swept by a
 * ball of radius MinorRadius (the tube). φ is the distance to that circle
 * minus MinorRadius: exact inside and outside as long as the tube does not
 * overlap itself, which is why MinorRadius <= MajorRadius is required.
 * Lipschitz constant 1. Axis need not be unit length but must not be zero;
 * both radii must be positive. Otherwise the function is NaN (see
 * vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive
 */
#ifndef vtkSignedDistanceTorus_h
#define vtkSignedDistanceTorus_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceTorus : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceTorus* New();
  vtkTypeMacro(vtkSignedDistanceTorus, vtkSignedDistancePrimitive);
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
   * The center of the torus (default 0, 0, 0).
   */
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /**
   * The axis of symmetry, normal to the plane of the core circle (default
   * 0, 0, 1; normalized when evaluated; must not be zero).
   */
  vtkSetVector3Macro(Axis, double);
  vtkGetVector3Macro(Axis, double);
  ///@}

  ///@{
  /**
   * The radius of the core circle (default 0.5; must be positive).
   */
  vtkSetMacro(MajorRadius, double);
  vtkGetMacro(MajorRadius, double);
  ///@}

  ///@{
  /**
   * The radius of the tube (default 0.2; must be positive and at most
   * MajorRadius).
   */
  vtkSetMacro(MinorRadius, double);
  vtkGetMacro(MinorRadius, double);
  ///@}

protected:
  vtkSignedDistanceTorus();
  ~vtkSignedDistanceTorus() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double Axis[3] = { 0.0, 0.0, 1.0 };
  double MajorRadius = 0.5;
  double MinorRadius = 0.2;

private:
  vtkSignedDistanceTorus(const vtkSignedDistanceTorus&) = delete;
  void operator=(const vtkSignedDistanceTorus&) = delete;
};

#endif
