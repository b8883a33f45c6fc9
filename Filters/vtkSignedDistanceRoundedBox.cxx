#include "vtkSignedDistanceRoundedBox.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

#include <cmath>

vtkStandardNewMacro(vtkSignedDistanceRoundedBox);

namespace
{
gridfree::RoundedBoxDistance<3> Core(vtkSignedDistanceRoundedBox* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::RoundedBoxDistance<3>(
    ToVec3(self->GetCenter()), ToVec3(self->GetHalfExtents()), self->GetRounding());
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceRoundedBox* primitive)
{
  return std::make_shared<const RoundedBoxDistance<3>>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceRoundedBox::vtkSignedDistanceRoundedBox() = default;
vtkSignedDistanceRoundedBox::~vtkSignedDistanceRoundedBox() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceRoundedBox::GetParameterProblem()
{
  using namespace gridfree::primitive;
  if (!IsFinite3(this->Center))
  {
    return "Center must be finite";
  }
  for (double h : this->HalfExtents)
  {
    if (!IsPositive(h))
    {
      return "every HalfExtents component must be positive and finite";
    }
  }
  if (!std::isfinite(this->Rounding))
  {
    return "Rounding must be finite";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceRoundedBox::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceRoundedBox::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceRoundedBox::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceRoundedBox::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "HalfExtents: (" << this->HalfExtents[0] << ", " << this->HalfExtents[1] << ", "
     << this->HalfExtents[2] << ")\n";
  os << indent << "Rounding: " << this->Rounding << "\n";
}
