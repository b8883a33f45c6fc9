#include "vtkSignedDistanceCylinder.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistanceCylinder);

namespace
{
gridfree::CylinderDistance Core(vtkSignedDistanceCylinder* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::CylinderDistance(ToVec3(self->GetCenter()), ToVec3(self->GetAxis()),
    self->GetRadius(), self->GetHalfHeight());
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceCylinder* primitive)
{
  return std::make_shared<const CylinderDistance>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceCylinder::vtkSignedDistanceCylinder() = default;
vtkSignedDistanceCylinder::~vtkSignedDistanceCylinder() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceCylinder::GetParameterProblem()
{
  using namespace gridfree::primitive;
  if (!IsFinite3(this->Center))
  {
    return "Center must be finite";
  }
  if (!IsDirection(this->Axis))
  {
    return "Axis must be a finite, non-zero vector";
  }
  if (!IsPositive(this->Radius))
  {
    return "Radius must be positive and finite";
  }
  if (!IsPositive(this->HalfHeight))
  {
    return "HalfHeight must be positive and finite";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceCylinder::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceCylinder::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceCylinder::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceCylinder::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "Axis: (" << this->Axis[0] << ", " << this->Axis[1] << ", " << this->Axis[2]
     << ")\n";
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "HalfHeight: " << this->HalfHeight << "\n";
}
