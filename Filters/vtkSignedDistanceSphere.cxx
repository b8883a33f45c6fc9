#include "vtkSignedDistanceSphere.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistanceSphere);

namespace
{
gridfree::SphereDistance<3> Core(vtkSignedDistanceSphere* self)
{
  return gridfree::SphereDistance<3>(gridfree::primitive::ToVec3(self->GetCenter()), self->GetRadius());
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceSphere* primitive)
{
  return std::make_shared<const SphereDistance<3>>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceSphere::vtkSignedDistanceSphere() = default;
vtkSignedDistanceSphere::~vtkSignedDistanceSphere() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceSphere::GetParameterProblem()
{
  using namespace gridfree::primitive;
  if (!IsFinite3(this->Center))
  {
    return "Center must be finite";
  }
  if (!IsPositive(this->Radius))
  {
    return "Radius must be positive and finite";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceSphere::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceSphere::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceSphere::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceSphere::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "Radius: " << this->Radius << "\n";
}
