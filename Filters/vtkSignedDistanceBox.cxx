#include "vtkSignedDistanceBox.h"

#include "vtkSignedDistancePrimitiveInternals.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkSignedDistanceBox);

namespace
{
gridfree::BoxDistance<3> Core(vtkSignedDistanceBox* self)
{
  using gridfree::primitive::ToVec3;
  return gridfree::BoxDistance<3>(ToVec3(self->GetCenter()), ToVec3(self->GetHalfExtents()));
}
} // namespace

gridfree::SharedDistance3 gridfree::MakeCoreDistance(vtkSignedDistanceBox* primitive)
{
  return std::make_shared<const BoxDistance<3>>(Core(primitive));
}

//------------------------------------------------------------------------------
vtkSignedDistanceBox::vtkSignedDistanceBox() = default;
vtkSignedDistanceBox::~vtkSignedDistanceBox() = default;

//------------------------------------------------------------------------------
const char* vtkSignedDistanceBox::GetParameterProblem()
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
  return nullptr;
}

//------------------------------------------------------------------------------
double vtkSignedDistanceBox::EvaluateFunction(double x[3])
{
  return gridfree::primitive::ValueOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x);
}

//------------------------------------------------------------------------------
void vtkSignedDistanceBox::EvaluateGradient(double x[3], double g[3])
{
  gridfree::primitive::GradientOrNaN(
    this->GetParameterProblem(), [this] { return Core(this); }, x, g);
}

//------------------------------------------------------------------------------
bool vtkSignedDistanceBox::GetLocalZeroSetBounds(double bounds[6])
{
  gridfree::primitive::StoreBounds(Core(this).Bounds(), bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkSignedDistanceBox::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "HalfExtents: (" << this->HalfExtents[0] << ", " << this->HalfExtents[1] << ", "
     << this->HalfExtents[2] << ")\n";
}
