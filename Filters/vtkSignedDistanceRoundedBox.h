/**
 * @class   vtkSignedDistanceRoundedBox
 * @brief   exact signed distance to an axis-aligned box with rounded edges
 *
 * The box [Center − HalfExtents, Center + HalfExtents] with its edges and
 * corners rounded by radius Rounding: the inner box of half extents
 * HalfExtents − Rounding grown by a ball of that radius, so HalfExtents are
 * the outer half extents and the bounds do not change with the rounding.
 * Exact inside and outside (Lipschitz constant 1). Rounding is clamped to
 * [0, smallest half extent] when evaluated (0 gives the sharp box, the
 * largest value a slab with fully rounded rims). Every half extent must be
 * positive and finite and Rounding finite; otherwise the function is NaN
 * (see vtkSignedDistancePrimitive).
 *
 * @sa vtkSignedDistancePrimitive vtkSignedDistanceBox
 */
#ifndef vtkSignedDistanceRoundedBox_h
#define vtkSignedDistanceRoundedBox_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkSignedDistancePrimitive.h"

class GRIDFREEFILTERS_EXPORT vtkSignedDistanceRoundedBox : public vtkSignedDistancePrimitive
{
public:
  static vtkSignedDistanceRoundedBox* New();
  vtkTypeMacro(vtkSignedDistanceRoundedBox, vtkSignedDistancePrimitive);
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
   * Half the outer edge lengths along x, y and z (default 0.5, 0.5, 0.5;
   * each must be positive).
   */
  vtkSetVector3Macro(HalfExtents, double);
  vtkGetVector3Macro(HalfExtents, double);
  ///@}

  ///@{
  /**
   * Radius of the rounded edges and corners (default 0.1; clamped to
   * [0, smallest half extent] when evaluated; must be finite).
   */
  vtkSetMacro(Rounding, double);
  vtkGetMacro(Rounding, double);
  ///@}

protected:
  vtkSignedDistanceRoundedBox();
  ~vtkSignedDistanceRoundedBox() override;

  const char* GetParameterProblem() override;
  bool GetLocalZeroSetBounds(double bounds[6]) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double HalfExtents[3] = { 0.5, 0.5, 0.5 };
  double Rounding = 0.1;

private:
  vtkSignedDistanceRoundedBox(const vtkSignedDistanceRoundedBox&) = delete;
  void operator=(const vtkSignedDistanceRoundedBox&) = delete;
};

#endif
