/**
 * @class   vtkSignedDistanceBox
 * @brief   exact signed distance to an axis-aligned box
 *
 * The box [Center − HalfExtents, Center + HalfExtents]. The value is the
 * Euclidean distance to the box's surface, exact inside and outside (unlike
 * vtkBox, whose value inside is exact but whose box is given by its bounds),
 * so its Lipschitz constant is 1. The gradient is the outward normal of the
 * nearest face inside and the unit vector from the closest surface point
 * outside. Every half extent must be positive and finite; otherwise the
 * function is NaN (see vtkSignedDistancePrimitive). Rotate or move it with a
 * Transform (a rigid motion keeps it a distance).
 *
 * @sa vtkSignedDistancePrimitive vtkSignedDistanceRoundedBox vtkBox
 */
#ifndef vtkSignedDistanceBox_h
#define vtkSignedDistanceBox_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceBox : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceBox* New();
  vtkTypeMacro(vtkSignedDistanceBox, vtkSignedDistancePrimitive);
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
   * The center of the box (default 0, 0, 0).
   */
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /**
   * Half the box's edge lengths along x, y and z (default 0.5, 0.5, 0.5;
   * each must be positive).
   */
  vtkSetVector3Macro(HalfExtents, double);
  vtkGetVector3Macro(HalfExtents, double);
  ///@}

protected:
  vtkSignedDistanceBox();
  ~vtkSignedDistanceBox() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double HalfExtents[3] = { 0.5, 0.5, 0.5 };

private:
  vtkSignedDistanceBox(const vtkSignedDistanceBox&) = delete;
  void operator=(const vtkSignedDistanceBox&) = delete;
};

#endif
