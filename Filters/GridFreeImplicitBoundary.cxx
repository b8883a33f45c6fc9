#include "GridFreeImplicitBoundary.h"

#include "vtkAbstractTransform.h"
#include "vtkBox.h"
#include "vtkImplicitBoolean.h"
#include "vtkImplicitFunction.h"
#include "vtkImplicitFunctionCollection.h"
#include "vtkSphere.h"

#include <cmath>

namespace gridfree
{
//------------------------------------------------------------------------------
VtkImplicitFunctionDistance::VtkImplicitFunctionDistance(
  vtkImplicitFunction* function, double lipschitz)
  : Function(function)
  , L(lipschitz)
{
  if (!function)
  {
    throw std::invalid_argument("no implicit function");
  }
  if (!(lipschitz > 0.0) || !std::isfinite(lipschitz))
  {
    throw std::invalid_argument("the Lipschitz bound must be positive and finite");
  }
  // A transform updates itself lazily on first use: do it now, on one
  // thread, so the walks only read it.
  if (vtkAbstractTransform* t = function->GetTransform())
  {
    t->Update();
  }
  if (!ImplicitFunctionBounds(function, this->Box))
  {
    this->Box = BoundingBox<3>();
  }
}

//------------------------------------------------------------------------------
double VtkImplicitFunctionDistance::Value(const Vec3& x) const
{
  double p[3] = { x[0], x[1], x[2] };
  return this->Function->FunctionValue(p);
}

//------------------------------------------------------------------------------
Vec3 VtkImplicitFunctionDistance::Gradient(const Vec3& x) const
{
  double p[3] = { x[0], x[1], x[2] };
  double g[3];
  this->Function->FunctionGradient(p, g);
  return Vec3(g[0], g[1], g[2]);
}

//------------------------------------------------------------------------------
bool ImplicitFunctionBounds(vtkImplicitFunction* f, BoundingBox<3>& box)
{
  if (!f || f->GetTransform())
  {
    return false;
  }
  if (auto* sphere = vtkSphere::SafeDownCast(f))
  {
    const double* c = sphere->GetCenter();
    const double r = sphere->GetRadius();
    box = BoundingBox<3>(Vec3(c[0] - r, c[1] - r, c[2] - r), Vec3(c[0] + r, c[1] + r, c[2] + r));
    return true;
  }
  if (auto* b = vtkBox::SafeDownCast(f))
  {
    double bounds[6];
    b->GetBounds(bounds);
    box = BoundingBox<3>(
      Vec3(bounds[0], bounds[2], bounds[4]), Vec3(bounds[1], bounds[3], bounds[5]));
    return true;
  }
  auto* boolean = vtkImplicitBoolean::SafeDownCast(f);
  if (!boolean || !boolean->GetFunction() || boolean->GetFunction()->GetNumberOfItems() == 0)
  {
    return false;
  }
  const int op = boolean->GetOperationType();
  vtkImplicitFunctionCollection* functions = boolean->GetFunction();
  BoundingBox<3> result;
  bool first = true;
  functions->InitTraversal();
  while (vtkImplicitFunction* child = functions->GetNextItem())
  {
    BoundingBox<3> childBox;
    const bool known = ImplicitFunctionBounds(child, childBox);
    if (op == vtkImplicitBoolean::VTK_INTERSECTION)
    {
      // One bounded operand bounds the intersection.
      if (known)
      {
        result = first || result.IsEmpty()
          ? childBox
          : BoundingBox<3>(result.Min.cwiseMax(childBox.Min), result.Max.cwiseMin(childBox.Max));
        first = false;
      }
      continue;
    }
    if (op == vtkImplicitBoolean::VTK_DIFFERENCE)
    {
      // Only the first operand's zero set can bound a difference.
      if (!known)
      {
        return false;
      }
      box = childBox;
      return true;
    }
    // Union (and union of magnitudes): every operand must be bounded.
    if (!known)
    {
      return false;
    }
    result.Expand(childBox);
    first = false;
  }
  if (first)
  {
    return false;
  }
  box = result;
  return true;
}

} // namespace gridfree
