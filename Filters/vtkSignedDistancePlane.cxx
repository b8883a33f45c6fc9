#include "vtkSignedDistancePlane.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistancePlane);

namespace
{
gridfree::PlaneDistance<3> Core(vtkSignedDistancePlane* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::PlaneDistance<3>(ToVec3(self->GetOrigin()), ToVec3(self->GetNormal()));
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistancePlane* primitive)
{
  return std::make_shared<const PlaneDistance<3>>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistancePlane::vtkSignedDistancePlane() = default;
vtkSignedDistancePlane::~vtkSignedDistancePlane() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistancePlane::GetParameterProblem()
{
  using namespace gridfree::primitive;
  if (!IsFinite3(this->Origin))
  {
    return "Origin must be finite";
  }
  if (!IsDirection(this->Normal))
  {
    return "Normal must be a finite, non-zero vector";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistancePlane::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistancePlane::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
// A half-space has no bounded zero set.
bool vtkSignedDistancePlane::GetLocalZeroSetBounds(double*)
{
  return false;
}

//------------------------------------------------------------------------------
void vtkSignedDistancePlane::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Origin: (" << this->Origin[0] << ", " << this->Origin[1] << ", "
     << this->Origin[2] << ")\n";
  os << indent << "Normal: (" << this->Normal[0] << ", " << this->Normal[1] << ", "
     << this->Normal[2] << ")\n";
}
