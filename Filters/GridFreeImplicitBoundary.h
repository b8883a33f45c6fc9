// Turns a vtkImplicitFunction into the estimator core's implicit boundary:
// the module's exact signed distances (vtkSignedDistancePrimitive) and
// vtkImplicitBoolean trees of them become core functions (CsgDistance), with
// exact gradients, no VTK calls and Lipschitz constant 1; any other function
// is called through VTK with the user's Lipschitz bound. Also finds the box
// of the zero set where the function type makes it known. The check of the
// bound is the core's ObservedLipschitz (SignedDistance.h).
// Private to the GridFree::Filters module.
#ifndef GridFreeImplicitBoundary_h
#define GridFreeImplicitBoundary_h

#include <gridfree/implicit/SignedDistance.h>

#include "vtkSmartPointer.h"

#include <memory>
#include <string>

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

// The box of f's zero set when it is known: a vtkSphere or vtkBox without a
// Transform, a bounded vtkSignedDistancePrimitive (without a Transform, or
// with a linear one: GetZeroSetBounds), or a vtkImplicitBoolean of such
// without a Transform of its own; false otherwise.
bool ImplicitFunctionBounds(vtkImplicitFunction* f, BoundingBox<3>& box);

// The exact core function of f when f is a vtkSignedDistancePrimitive with
// valid parameters and no Transform, or a vtkImplicitBoolean without a
// Transform whose functions are all such (recursively), with VTK's meaning
// of the operation: union = min, intersection = max, difference = the first
// function minus all the others (max(φ1, −φ2, −φ3, …)). The result gives the
// same values as f->FunctionValue. Null for anything else (other VTK
// functions, Transforms, UnionOfMagnitudes, empty booleans).
std::shared_ptr<const SignedDistanceFunction<3>> MakeExactImplicitDistance(vtkImplicitFunction* f);

// The error of the first vtkSignedDistancePrimitive with invalid parameters
// in f's tree (f itself or inside vtkImplicitBooleans); empty when none.
std::string InvalidPrimitiveError(vtkImplicitFunction* f);

// A Lipschitz bound that f is known to satisfy: the primitives' constants
// (1, or a linear Transform's largest singular value), and for booleans the
// largest of their functions' (min, max and |·| keep it) times their own
// Transform's factor. 0 when unknown (any other VTK function, a non-linear
// Transform, an empty boolean).
double KnownLipschitzBound(vtkImplicitFunction* f);

} // namespace gridfree

#endif
