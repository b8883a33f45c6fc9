#include "GridFreeImplicitBoundary.h"

#include <gridfree/implicit/CsgFunctions.h>
#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkAbstractTransform.h"
#include "vtkBox.h"
#include "vtkImplicitBoolean.h"
#include "vtkImplicitFunction.h"
#include "vtkImplicitFunctionCollection.h"
#include "vtkSignedDistanceBox.h"
#include "vtkSignedDistanceCapsule.h"
#include "vtkSignedDistanceCylinder.h"
#include "vtkSignedDistancePlane.h"
#include "vtkSignedDistancePrimitive.h"
#include "vtkSignedDistanceRoundedBox.h"
#include "vtkSignedDistanceSphere.h"
#include "vtkSignedDistanceTorus.h"
#include "vtkSphere.h"

#include <algorithm>
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
  if (auto* primitive = vtkSignedDistancePrimitive::SafeDownCast(f))
  {
    // Handles its own Transform (linear ones map the box exactly).
    double bounds[6];
    if (!primitive->GetZeroSetBounds(bounds))
    {
      return false;
    }
    box = BoundingBox<3>(
      Vec3(bounds[0], bounds[2], bounds[4]), Vec3(bounds[1], bounds[3], bounds[5]));
    return true;
  }
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

//------------------------------------------------------------------------------
std::shared_ptr<const SignedDistanceFunction<3>> MakeExactImplicitDistance(vtkImplicitFunction* f)
{
  if (!f || f->GetTransform())
  {
    return nullptr;
  }
  if (auto* primitive = vtkSignedDistancePrimitive::SafeDownCast(f))
  {
    if (!primitive->HasValidParameters())
    {
      return nullptr;
    }
    if (auto* p = vtkSignedDistanceSphere::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistanceBox::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistanceRoundedBox::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistanceTorus::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistanceCylinder::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistanceCapsule::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    if (auto* p = vtkSignedDistancePlane::SafeDownCast(f))
    {
      return MakeCoreDistance(p);
    }
    return nullptr; // a subclass from elsewhere: only VTK knows how to evaluate it
  }
  auto* boolean = vtkImplicitBoolean::SafeDownCast(f);
  if (!boolean || !boolean->GetFunction())
  {
    return nullptr;
  }
  CsgOperation op;
  switch (boolean->GetOperationType())
  {
    case vtkImplicitBoolean::VTK_UNION:
      op = CsgOperation::Union;
      break;
    case vtkImplicitBoolean::VTK_INTERSECTION:
      op = CsgOperation::Intersection;
      break;
    case vtkImplicitBoolean::VTK_DIFFERENCE:
      op = CsgOperation::Difference;
      break;
    default:
      return nullptr; // union of magnitudes, min |φi|, has no solid meaning
  }
  // A left fold: ((φ1 op φ2) op φ3) …. min and max are associative, and
  // VTK's difference max(φ1, −φ2, −φ3, …) is ((φ1 − φ2) − φ3) …. Every child
  // has L = 1, so CsgDistance's normalization divides by 1 and the values
  // are bit for bit those of vtkImplicitBoolean.
  std::shared_ptr<const SignedDistanceFunction<3>> tree;
  vtkImplicitFunctionCollection* functions = boolean->GetFunction();
  vtkCollectionSimpleIterator it;
  functions->InitTraversal(it);
  while (vtkImplicitFunction* child = functions->GetNextImplicitFunction(it))
  {
    auto exact = MakeExactImplicitDistance(child);
    if (!exact)
    {
      return nullptr;
    }
    tree = tree ? std::make_shared<const CsgDistance<3>>(op, tree, exact) : exact;
  }
  return tree;
}

//------------------------------------------------------------------------------
std::string InvalidPrimitiveError(vtkImplicitFunction* f)
{
  if (auto* primitive = vtkSignedDistancePrimitive::SafeDownCast(f))
  {
    return primitive->GetParameterError();
  }
  auto* boolean = vtkImplicitBoolean::SafeDownCast(f);
  if (!boolean || !boolean->GetFunction())
  {
    return std::string();
  }
  vtkImplicitFunctionCollection* functions = boolean->GetFunction();
  vtkCollectionSimpleIterator it;
  functions->InitTraversal(it);
  while (vtkImplicitFunction* child = functions->GetNextImplicitFunction(it))
  {
    std::string error = InvalidPrimitiveError(child);
    if (!error.empty())
    {
      return error;
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
double KnownLipschitzBound(vtkImplicitFunction* f)
{
  if (auto* primitive = vtkSignedDistancePrimitive::SafeDownCast(f))
  {
    return primitive->GetLipschitzConstant();
  }
  auto* boolean = vtkImplicitBoolean::SafeDownCast(f);
  if (!boolean || !boolean->GetFunction() || boolean->GetFunction()->GetNumberOfItems() == 0)
  {
    return 0.0;
  }
  double largest = 0.0;
  vtkImplicitFunctionCollection* functions = boolean->GetFunction();
  vtkCollectionSimpleIterator it;
  functions->InitTraversal(it);
  while (vtkImplicitFunction* child = functions->GetNextImplicitFunction(it))
  {
    const double bound = KnownLipschitzBound(child);
    if (!(bound > 0.0))
    {
      return 0.0;
    }
    largest = std::max(largest, bound);
  }
  return largest * vtkSignedDistancePrimitive::TransformLipschitzFactor(boolean->GetTransform());
}

} // namespace gridfree
