// The accessors of the settings a filter keeps in one gridfree::SolveSettings
// (vtkWalkOnSpheresAlgorithm's GetSettings()): defined once here for the
// base's sampling settings and the subclasses' own, so that a property's
// clamp and its Modified() behave alike in each. Use in a .cxx only.
// Private to the GridFree::Filters module.
#ifndef GridFreeSettingAccessors_h
#define GridFreeSettingAccessors_h

#include "GridFreeSolveSettings.h"

#include "vtkImplicitFunction.h"
#include "vtkIndent.h"

#include <algorithm>
#include <ostream>
#include <string>

namespace gridfree
{
// PrintSelf's lines for the settings beyond the sampling ones (which the
// base prints): the boundary, the equation, the target and the derivatives.
inline void PrintProblemSettings(std::ostream& os, vtkIndent indent, const SolveSettings& s)
{
  const auto text = [](const std::string& t) { return t.empty() ? std::string("(none)") : t; };
  const auto onOff = [](bool b) { return b ? "On" : "Off"; };
  os << indent << "ImplicitBoundary: " << s.ImplicitBoundary << "\n";
  os << indent << "LipschitzBound: " << s.LipschitzBound << "\n";
  os << indent << "CsgOperation: " << CodeOf(s.CsgOperation) << "\n";
  os << indent << "CsgBlendRadius: " << s.CsgBlendRadius << "\n";
  os << indent << "BoundaryValueExpression: " << text(s.BoundaryValueExpression) << "\n";
  os << indent << "BoundaryLaplacianExpression: " << text(s.BoundaryLaplacianExpression) << "\n";
  os << indent << "TwoSidedBoundaryValues: " << onOff(s.TwoSidedBoundaryValues) << "\n";
  os << indent << "MixedBoundaryConditions: " << onOff(s.MixedBoundaryConditions) << "\n";
  os << indent << "Equation: " << CodeOf(s.Equation) << "\n";
  os << indent << "ScreeningCoefficient: " << s.ScreeningCoefficient << "\n";
  os << indent << "DiffusionCoefficient: " << s.DiffusionCoefficient << "\n";
  os << indent << "AbsorptionCoefficient: " << s.AbsorptionCoefficient << "\n";
  os << indent << "CoefficientSmoothing: " << s.CoefficientSmoothing << "\n";
  os << indent << "DiffusionFromArray: " << onOff(s.DiffusionFromArray) << "\n";
  os << indent << "AbsorptionFromArray: " << onOff(s.AbsorptionFromArray) << "\n";
  os << indent << "SourceTermFromArray: " << onOff(s.SourceTermFromArray) << "\n";
  os << indent << "DiffusionExpression: " << text(s.DiffusionExpression) << "\n";
  os << indent << "AbsorptionExpression: " << text(s.AbsorptionExpression) << "\n";
  os << indent << "SourceExpression: " << text(s.SourceExpression) << "\n";
  os << indent << "SourceSampling: " << CodeOf(s.SourceSampling) << "\n";
  os << indent << "ScreenedSteps: " << CodeOf(s.ScreenedSteps) << "\n";
  os << indent << "PeakSteps: " << CodeOf(s.PeakSteps) << "\n";
  os << indent << "SourceOperator: " << CodeOf(s.SourceOperator) << "\n";
  os << indent << "BiharmonicStrategy: " << CodeOf(s.BiharmonicStrategy) << "\n";
  os << indent << "NestedWalks: " << s.NestedWalks << "\n";
  os << indent << "TargetStandardError: " << s.TargetStandardError << "\n";
  os << indent << "TargetErrorIsRelative: " << onOff(s.TargetErrorIsRelative) << "\n";
  os << indent << "WalkOnWhereUnreliable: " << s.WalkOnWhereUnreliable << "\n";
  os << indent << "ComputeGradient: " << onOff(s.ComputeGradient) << "\n";
  os << indent << "ComputeHessian: " << onOff(s.ComputeHessian) << "\n";
  os << indent << "ControlVariates: " << onOff(s.ControlVariates) << "\n";
  os << indent << "AntitheticPairs: " << onOff(s.AntitheticPairs) << "\n";
  os << indent << "NearBoundarySplitting: " << onOff(s.NearBoundarySplitting) << "\n";
  os << indent << "ComputeDirectionalDerivative: " << onOff(s.ComputeDirectionalDerivative)
     << "\n";
  os << indent << "DerivativeDirection: " << s.DerivativeDirection[0] << " "
     << s.DerivativeDirection[1] << " " << s.DerivativeDirection[2] << "\n";
}
} // namespace gridfree

// Set clamps to [lo, hi] and marks the filter modified when the value
// changes; Get returns it.
#define GRIDFREE_SETTING_ACCESSORS(Class, Name, Type, lo, hi)                                      \
  void Class::Set##Name(Type value)                                                                \
  {                                                                                                \
    value = std::min<Type>(std::max<Type>(value, lo), hi);                                         \
    if (this->GetSettings().Name != value)                                                         \
    {                                                                                              \
      this->GetSettings().Name = value;                                                            \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  Type Class::Get##Name() { return this->GetSettings().Name; }

// A choice's accessors: the integer code (vtkWalkOnSpheresSolver's
// enumeration) clamped to [0, hi], stored as the core's typed choice.
#define GRIDFREE_CHOICE_ACCESSORS(Class, Name, Choice, hi)                                         \
  void Class::Set##Name(int code)                                                                  \
  {                                                                                                \
    const Choice value = static_cast<Choice>(std::min(std::max(code, 0), hi));                     \
    if (this->GetSettings().Name != value)                                                         \
    {                                                                                              \
      this->GetSettings().Name = value;                                                            \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  int Class::Get##Name() { return gridfree::CodeOf(this->GetSettings().Name); }

// An expression's accessors: null clears it (the empty expression).
#define GRIDFREE_EXPRESSION_ACCESSORS(Class, Name)                                                 \
  void Class::Set##Name(const char* expression)                                                    \
  {                                                                                                \
    const std::string text = expression ? expression : "";                                         \
    if (text != this->GetSettings().Name)                                                          \
    {                                                                                              \
      this->GetSettings().Name = text;                                                             \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  const char* Class::Get##Name() { return this->GetSettings().Name.c_str(); }

// The implicit boundary's accessors: the filter holds a reference to the
// function the settings point to (its destructor sets it to null).
#define GRIDFREE_IMPLICIT_BOUNDARY_ACCESSORS(Class)                                                \
  void Class::SetImplicitBoundary(vtkImplicitFunction* function)                                   \
  {                                                                                                \
    vtkImplicitFunction*& kept = this->GetSettings().ImplicitBoundary;                             \
    if (function != kept)                                                                          \
    {                                                                                              \
      if (function)                                                                                \
      {                                                                                            \
        function->Register(this);                                                                  \
      }                                                                                            \
      if (kept)                                                                                    \
      {                                                                                            \
        kept->UnRegister(this);                                                                    \
      }                                                                                            \
      kept = function;                                                                             \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  vtkImplicitFunction* Class::GetImplicitBoundary() { return this->GetSettings().ImplicitBoundary; }

#endif
