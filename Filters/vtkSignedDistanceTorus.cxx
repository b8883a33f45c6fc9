#include "vtkSignedDistanceTorus.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistanceTorus);

namespace
{
gridfree::TorusDistance Core(vtkSignedDistanceTorus* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::TorusDistance(ToVec3(self->GetCenter()), ToVec3(self->GetAxis()),
    self->GetMajorRadius(), self->GetMinorRadius());
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceTorus* primitive)
{
  return std::make_shared<const TorusDistance>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceTorus::vtkSignedDistanceTorus() = default;
vtkSignedDistanceTorus::~vtkSignedDistanceTorus() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceTorus::GetParameterProblem()
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
  if (!IsPositive(this->MajorRadius))
  {
    return "MajorRadius must be positive and finite";
  }
  if (!IsPositive(this->MinorRadius))
  {
    return "MinorRadius must be positive and finite";
  }
  if (this->MinorRadius > this->MajorRadius)
  {
    return "MinorRadius must not exceed MajorRadius (a self-intersecting tube has no exact "
           "distance)";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceTorus::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceTorus::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceTorus::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceTorus::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "Axis: (" << this->Axis[0] << ", " << this->Axis[1] << ", " << this->Axis[2]
     << ")\n";
  os << indent << "MajorRadius: " << this->MajorRadius << "\n";
  os << indent << "MinorRadius: " << this->MinorRadius << "\n";
}
