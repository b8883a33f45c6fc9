#include "vtkSignedDistanceCapsule.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistanceCapsule);

namespace
{
gridfree::CapsuleDistance<3> Core(vtkSignedDistanceCapsule* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::CapsuleDistance<3>(
    ToVec3(self->GetPoint1()), ToVec3(self->GetPoint2()), self->GetRadius());
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceCapsule* primitive)
{
  return std::make_shared<const CapsuleDistance<3>>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceCapsule::vtkSignedDistanceCapsule() = default;
vtkSignedDistanceCapsule::~vtkSignedDistanceCapsule() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceCapsule::GetParameterProblem()
{
  using namespace gridfree::primitive;
  if (!IsFinite3(this->Point1) || !IsFinite3(this->Point2))
  {
    return "Point1 and Point2 must be finite";
  }
  if (!IsPositive(this->Radius))
  {
    return "Radius must be positive and finite";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceCapsule::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceCapsule::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceCapsule::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceCapsule::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Point1: (" << this->Point1[0] << ", " << this->Point1[1] << ", "
     << this->Point1[2] << ")\n";
  os << indent << "Point2: (" << this->Point2[0] << ", " << this->Point2[1] << ", "
     << this->Point2[2] << ")\n";
  os << indent << "Radius: " << this->Radius << "\n";
}
