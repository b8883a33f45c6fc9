#include "vtkWalkOnSpheresSolverDriver.h"

#include "GridFreeArraySelection.h"
#include "GridFreePointEstimates.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"
#include "GridFreeWholeInputRequest.h"

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <exception>
#include <string>

struct vtkWalkOnSpheresSolverDriver::Internals
{
  gridfree::SolveSettings Settings;
  vtkSmartPointer<vtkImplicitFunction> Implicit; // Settings.ImplicitBoundary's owner
  gridfree::ProblemBuilder Builder;
  gridfree::BuiltProblem Problem;
  std::vector<std::string> Warnings; // distinct, in order of arrival
  bool EstimateFailed = false;
};

vtkWalkOnSpheresSolverDriver::vtkWalkOnSpheresSolverDriver()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(1);
  // Lines and samples need the gradient.
  this->Internal->Settings.ComputeGradient = true;
}

vtkWalkOnSpheresSolverDriver::~vtkWalkOnSpheresSolverDriver() = default;

void vtkWalkOnSpheresSolverDriver::SetBoundaryConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(BoundaryPort, output);
}
void vtkWalkOnSpheresSolverDriver::SetBoundaryData(vtkDataObject* data)
{
  this->SetInputData(BoundaryPort, data);
}
void vtkWalkOnSpheresSolverDriver::SetSourceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(SourcePort, output);
}
void vtkWalkOnSpheresSolverDriver::SetSourceData(vtkDataObject* data)
{
  this->SetInputData(SourcePort, data);
}

// A setting's accessors: Set clamps to [lo, hi] and marks the filter
// modified when the value changes.
#define GRIDFREE_DRIVER_SETTING(Name, Type, lo, hi)                                                \
  void vtkWalkOnSpheresSolverDriver::Set##Name(Type value)                                         \
  {                                                                                                \
    value = std::min<Type>(std::max<Type>(value, lo), hi);                                         \
    if (this->Internal->Settings.Name != value)                                                    \
    {                                                                                              \
      this->Internal->Settings.Name = value;                                                       \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  Type vtkWalkOnSpheresSolverDriver::Get##Name() { return this->Internal->Settings.Name; }

GRIDFREE_DRIVER_SETTING(Equation, int, 0, 3)
GRIDFREE_DRIVER_SETTING(ScreeningCoefficient, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_DRIVER_SETTING(WalksPerPoint, int, 2, VTK_INT_MAX)
GRIDFREE_DRIVER_SETTING(Epsilon, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_DRIVER_SETTING(EpsilonIsRelative, bool, false, true)
GRIDFREE_DRIVER_SETTING(MaxSteps, int, 1, VTK_INT_MAX)
GRIDFREE_DRIVER_SETTING(Seed, int, VTK_INT_MIN, VTK_INT_MAX)
GRIDFREE_DRIVER_SETTING(NumberOfThreads, int, 0, VTK_INT_MAX)
GRIDFREE_DRIVER_SETTING(ControlVariates, bool, false, true)
GRIDFREE_DRIVER_SETTING(AntitheticPairs, bool, false, true)
GRIDFREE_DRIVER_SETTING(LipschitzBound, double, 1e-300, VTK_DOUBLE_MAX)
GRIDFREE_DRIVER_SETTING(CsgOperation, int, 0, 3)
GRIDFREE_DRIVER_SETTING(CsgBlendRadius, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_DRIVER_SETTING(TwoSidedBoundaryValues, bool, false, true)
GRIDFREE_DRIVER_SETTING(SourceSampling, int, 0, 3)
GRIDFREE_DRIVER_SETTING(SourceOperator, int, 0, 2)
GRIDFREE_DRIVER_SETTING(BiharmonicStrategy, int, 0, 1)
GRIDFREE_DRIVER_SETTING(NestedWalks, int, 1, VTK_INT_MAX)
#undef GRIDFREE_DRIVER_SETTING

// An expression's setter: null clears it.
#define GRIDFREE_DRIVER_EXPRESSION(Name)                                                           \
  void vtkWalkOnSpheresSolverDriver::Set##Name(const char* expression)                             \
  {                                                                                                \
    const std::string text = expression ? expression : "";                                         \
    if (text != this->Internal->Settings.Name)                                                     \
    {                                                                                              \
      this->Internal->Settings.Name = text;                                                        \
      this->Modified();                                                                            \
    }                                                                                              \
  }

GRIDFREE_DRIVER_EXPRESSION(SourceExpression)
GRIDFREE_DRIVER_EXPRESSION(BoundaryValueExpression)
GRIDFREE_DRIVER_EXPRESSION(BoundaryLaplacianExpression)
#undef GRIDFREE_DRIVER_EXPRESSION

void vtkWalkOnSpheresSolverDriver::SetImplicitBoundary(vtkImplicitFunction* function)
{
  if (function != this->Internal->Implicit)
  {
    this->Internal->Implicit = function;
    this->Internal->Settings.ImplicitBoundary = function;
    this->Modified();
  }
}

vtkImplicitFunction* vtkWalkOnSpheresSolverDriver::GetImplicitBoundary()
{
  return this->Internal->Implicit;
}

bool vtkWalkOnSpheresSolverDriver::GetLastBoundaryBuilt()
{
  return this->Internal->Builder.GetLastBoundaryBuilt();
}

// Editing the implicit function must re-execute the filter.
vtkMTimeType vtkWalkOnSpheresSolverDriver::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->Internal->Implicit)
  {
    time = std::max(time, this->Internal->Implicit->GetMTime());
  }
  return time;
}

int vtkWalkOnSpheresSolverDriver::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == BoundaryPort)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1); // an implicit boundary may replace it
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    if (port == SourcePort)
    {
      info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    }
  }
  return 1;
}

// Every input is needed whole.
int vtkWalkOnSpheresSolverDriver::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  for (int port = 0; port < this->GetNumberOfInputPorts(); ++port)
  {
    gridfree::RequestWholeInput(inputVector[port]->GetInformationObject(0));
  }
  return 1;
}

bool vtkWalkOnSpheresSolverDriver::BuildProblem(
  vtkDataObject* boundary, vtkDataObject* source, vtkDataSet* region)
{
  Internals& state = *this->Internal;
  state.Warnings.clear();
  state.EstimateFailed = false;
  gridfree::ProblemData data;
  data.Boundary = boundary;
  data.BoundaryPiece = boundary;
  data.Source = source;
  data.Region = region;
  return state.Builder.Build(
    this, state.Settings, gridfree::ArraySelections::Of(this), data, state.Problem);
}

bool vtkWalkOnSpheresSolverDriver::EstimateAt(const std::vector<std::array<double, 3>>& points,
  vtkPointData* arrays, double progress, double& seconds, vtkIdType& walks)
{
  Internals& state = *this->Internal;
  gridfree::PointEstimateRun run;
  run.ProgressBegin = progress;
  run.ProgressEnd = progress;
  run.Warn = [&state](const std::string& text) {
    if (std::find(state.Warnings.begin(), state.Warnings.end(), text) == state.Warnings.end())
    {
      state.Warnings.push_back(text);
    }
  };
  gridfree::PointEstimateSummary summary;
  bool completed = false;
  try
  {
    completed = gridfree::EstimateAtPoints(
      this, state.Problem, state.Settings, points, arrays, nullptr, run, summary);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Walk on spheres failed: " << e.what());
    state.EstimateFailed = true;
  }
  seconds += summary.Seconds;
  walks += static_cast<vtkIdType>(summary.WalksRun);
  return completed;
}

bool vtkWalkOnSpheresSolverDriver::GetEstimateFailed()
{
  return this->Internal->EstimateFailed;
}

const char* vtkWalkOnSpheresSolverDriver::GetSolutionName()
{
  return this->Internal->Problem.Name.c_str();
}

int vtkWalkOnSpheresSolverDriver::GetSolutionComponents()
{
  return this->Internal->Problem.Components;
}

void vtkWalkOnSpheresSolverDriver::ReportWarnings()
{
  for (const std::string& text : this->Internal->Warnings)
  {
    vtkWarningMacro(<< text);
  }
  this->Internal->Warnings.clear();
}

void vtkWalkOnSpheresSolverDriver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const gridfree::SolveSettings& s = this->Internal->Settings;
  os << indent << "Equation: " << s.Equation << "\n";
  os << indent << "ScreeningCoefficient: " << s.ScreeningCoefficient << "\n";
  os << indent << "SourceExpression: " << s.SourceExpression << "\n";
  os << indent << "ImplicitBoundary: " << s.ImplicitBoundary << "\n";
  os << indent << "BoundaryValueExpression: " << s.BoundaryValueExpression << "\n";
  os << indent << "BoundaryLaplacianExpression: " << s.BoundaryLaplacianExpression << "\n";
  os << indent << "LipschitzBound: " << s.LipschitzBound << "\n";
  os << indent << "CsgOperation: " << s.CsgOperation << "\n";
  os << indent << "CsgBlendRadius: " << s.CsgBlendRadius << "\n";
  os << indent << "TwoSidedBoundaryValues: " << s.TwoSidedBoundaryValues << "\n";
  os << indent << "SourceSampling: " << s.SourceSampling << "\n";
  os << indent << "SourceOperator: " << s.SourceOperator << "\n";
  os << indent << "BiharmonicStrategy: " << s.BiharmonicStrategy << "\n";
  os << indent << "NestedWalks: " << s.NestedWalks << "\n";
  os << indent << "WalksPerPoint: " << s.WalksPerPoint << "\n";
  os << indent << "Epsilon: " << s.Epsilon << "\n";
  os << indent << "EpsilonIsRelative: " << (s.EpsilonIsRelative ? "On" : "Off") << "\n";
  os << indent << "MaxSteps: " << s.MaxSteps << "\n";
  os << indent << "Seed: " << s.Seed << "\n";
  os << indent << "NumberOfThreads: " << s.NumberOfThreads << "\n";
  os << indent << "ControlVariates: " << (s.ControlVariates ? "On" : "Off") << "\n";
  os << indent << "AntitheticPairs: " << (s.AntitheticPairs ? "On" : "Off") << "\n";
}
