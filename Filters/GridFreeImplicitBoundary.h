// Turns a vtkImplicitFunction into the estimator core's implicit boundary
// (a SignedDistanceFunction<3> with the user's Lipschitz bound), and finds
// the box of its zero set where the function type makes it known. The check
// of the bound is the core's ObservedLipschitz (SignedDistance.h).
// Private to the GridFree::Filters module.
#ifndef GridFreeImplicitBoundary_h
#define GridFreeImplicitBoundary_h

#include "Geometry/SignedDistance.h"

#include "vtkSmartPointer.h"

class vtkImplicitFunction;

namespace gridfree
{
// φ(x) = f->FunctionValue(x). The function is called from several threads
// at once; VTK's implicit functions (sphere, plane, box, cylinder, boolean
// combinations, with or without a transform) only read their parameters.
class VtkImplicitFunctionDistance final : public SignedDistanceFunction<3>
{
public:
  VtkImplicitFunctionDistance(vtkImplicitFunction* function, double lipschitz);

  double Value(const Vec3& x) const override;
  Vec3 Gradient(const Vec3& x) const override;
  double Lipschitz() const override { return this->L; }
  BoundingBox<3> Bounds() const override { return this->Box; }

private:
  vtkSmartPointer<vtkImplicitFunction> Function;
  double L;
  BoundingBox<3> Box;
};

// The box of f's zero set when f is a vtkSphere, a vtkBox, or a
// vtkImplicitBoolean of such (no transforms); false when it is not known.
bool ImplicitFunctionBounds(vtkImplicitFunction* f, BoundingBox<3>& box);

} // namespace gridfree

#endif
