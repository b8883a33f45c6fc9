/**
 * @class   vtkSignedDistanceCapsule
 * @brief   exact signed distance to a capsule (a swept ball)
 *
 * The segment from Point1 to Point2 swept by a ball of radius Radius: a
 * cylinder with hemispherical ends. φ is the distance to the segment minus
 * Radius, exact inside and outside (Lipschitz constant 1). Point1 = Point2
 * is allowed (a ball). Radius must be positive and the points finite;
 * otherwise the function is NaN (see vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive vtkSignedDistanceCylinder
 */
#ifndef vtkSignedDistanceCapsule_h
#define vtkSignedDistanceCapsule_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceCapsule : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceCapsule* New();
  vtkTypeMacro(vtkSignedDistanceCapsule, vtkSignedDistancePrimitive);
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
   * The ends of the segment (default -0.5, 0, 0 and 0.5, 0, 0).
   */
  vtkSetVector3Macro(Point1, double);
  vtkGetVector3Macro(Point1, double);
  vtkSetVector3Macro(Point2, double);
  vtkGetVector3Macro(Point2, double);
  ///@}

  ///@{
  /**
   * The radius of the swept ball (default 0.25; must be positive).
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

protected:
  vtkSignedDistanceCapsule();
  ~vtkSignedDistanceCapsule() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Point1[3] = { -0.5, 0.0, 0.0 };
  double Point2[3] = { 0.5, 0.0, 0.0 };
  double Radius = 0.25;

private:
  vtkSignedDistanceCapsule(const vtkSignedDistanceCapsule&) = delete;
  void operator=(const vtkSignedDistanceCapsule&) = delete;
};

#endif
