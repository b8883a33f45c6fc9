#include "vtkSignedDistancePrimitive.h"

#include "vtkAbstractTransform.h"
#include "vtkLinearTransform.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"

#include <algorithm>
#include <cmath>

namespace
{
// The linear part A and translation t of a linear transform, T(x) = A x + t.
// vtkLinearTransform ignores the matrix's last row, so this is all of it.
bool AffineParts(vtkAbstractTransform* transform, double a[3][3], double t[3])
{
  auto* linear = vtkLinearTransform::SafeDownCast(transform);
  if (!linear)
  {
    return false;
  }
  vtkMatrix4x4* m = linear->GetMatrix(); // updates the transform
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      a[i][j] = m->GetElement(i, j);
    }
    t[i] = m->GetElement(i, 3);
  }
  return true;
}
} // namespace

//------------------------------------------------------------------------------
vtkSignedDistancePrimitive::vtkSignedDistancePrimitive() = default;
vtkSignedDistancePrimitive::~vtkSignedDistancePrimitive() = default;

//------------------------------------------------------------------------------
double vtkSignedDistancePrimitive::TransformLipschitzFactor(vtkAbstractTransform* transform)
{
  if (!transform)
  {
    return 1.0;
  }
  double a[3][3], t[3];
  if (!AffineParts(transform, a, t))
  {
    return 0.0;
  }
  // |A x − A y| ≤ σ_max |x − y|: the slope of φ∘T is at most σ_max times φ's.
  double u[3][3], w[3], vt[3][3];
  vtkMath::SingularValueDecomposition3x3(a, u, w, vt);
  const double sigma = std::max({ std::abs(w[0]), std::abs(w[1]), std::abs(w[2]) });
  return std::isfinite(sigma) ? sigma : 0.0;
}

//------------------------------------------------------------------------------
double vtkSignedDistancePrimitive::GetLipschitzConstant()
{
  return TransformLipschitzFactor(this->Transform);
}

//------------------------------------------------------------------------------
bool vtkSignedDistancePrimitive::GetZeroSetBounds(double bounds[6])
{
  if (this->GetParameterProblem())
  {
    return false;
  }
  double local[6];
  if (!this->GetLocalZeroSetBounds(local))
  {
    return false;
  }
  if (!this->Transform)
  {
    std::copy(local, local + 6, bounds);
    return true;
  }
  // FunctionValue(x) = φ(A x + t), so the world zero set is the preimage
  // A⁻¹(Z − t) of the local one; the preimage of a box is a parallelepiped,
  // bounded by the preimages of the box's eight corners.
  double a[3][3], t[3];
  if (!AffineParts(this->Transform, a, t))
  {
    return false;
  }
  const double det = vtkMath::Determinant3x3(a);
  if (!(std::abs(det) > 0.0) || !std::isfinite(det))
  {
    return false;
  }
  double inverse[3][3];
  vtkMath::Invert3x3(a, inverse);
  double result[6] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX,
    VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (int corner = 0; corner < 8; ++corner)
  {
    double y[3];
    for (int k = 0; k < 3; ++k)
    {
      y[k] = local[2 * k + ((corner >> k) & 1)] - t[k];
    }
    double x[3];
    vtkMath::Multiply3x3(inverse, y, x);
    for (int k = 0; k < 3; ++k)
    {
      result[2 * k] = std::min(result[2 * k], x[k]);
      result[2 * k + 1] = std::max(result[2 * k + 1], x[k]);
    }
  }
  for (double v : result)
  {
    if (!std::isfinite(v))
    {
      return false;
    }
  }
  std::copy(result, result + 6, bounds);
  return true;
}

//------------------------------------------------------------------------------
std::string vtkSignedDistancePrimitive::GetParameterError()
{
  const char* problem = this->GetParameterProblem();
  return problem ? std::string(this->GetClassName()) + ": " + problem : std::string();
}

//------------------------------------------------------------------------------
bool vtkSignedDistancePrimitive::HasValidParameters()
{
  return this->GetParameterProblem() == nullptr;
}

//------------------------------------------------------------------------------
void vtkSignedDistancePrimitive::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* problem = this->GetParameterProblem();
  os << indent << "ParameterError: " << (problem ? problem : "(none)") << "\n";
}
