#include "vtkWalkOnSpheresSolverDriver.h"

#include "GridFreeArraySelection.h"
#include "GridFreePointEstimates.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSettingAccessors.h"
#include "GridFreeSolveSettings.h"
#include "GridFreeWholeInputRequest.h"

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <exception>
#include <functional>
#include <string>

struct vtkWalkOnSpheresSolverDriver::Internals
{
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
  this->GetSettings().ComputeGradient = true;
  // As the solver (vtkWalkOnSpheresSolver::SetNearBoundarySplitting).
  this->GetSettings().NearBoundarySplitting = true;
}

vtkWalkOnSpheresSolverDriver::~vtkWalkOnSpheresSolverDriver()
{
  this->SetImplicitBoundary(nullptr);
}

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

GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, ScreeningCoefficient, double, 0.0, VTK_DOUBLE_MAX)
// Unclamped: the problem builder names a bad coefficient.
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, DiffusionCoefficient, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, AbsorptionCoefficient, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, CoefficientSmoothing, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, DiffusionFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, AbsorptionFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, SourceTermFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, ControlVariates, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, AntitheticPairs, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, NearBoundarySplitting, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, LipschitzBound, double, 1e-300, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, CsgBlendRadius, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, TwoSidedBoundaryValues, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, MixedBoundaryConditions, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolverDriver, NestedWalks, int, 1, VTK_INT_MAX)

GRIDFREE_CHOICE_ACCESSORS(vtkWalkOnSpheresSolverDriver, Equation, gridfree::Equation, 4)
GRIDFREE_CHOICE_ACCESSORS(vtkWalkOnSpheresSolverDriver, SourceSampling, gridfree::SourceSampling, 4)
GRIDFREE_CHOICE_ACCESSORS(vtkWalkOnSpheresSolverDriver, SourceOperator, gridfree::SourceOperator, 2)
GRIDFREE_CHOICE_ACCESSORS(vtkWalkOnSpheresSolverDriver, BiharmonicStrategy, gridfree::BiharmonicStrategy, 1)

void vtkWalkOnSpheresSolverDriver::SetCsgOperation(int code)
{
  const std::optional<gridfree::CsgOperation> value =
    gridfree::CsgOperationOfCode(std::min(std::max(code, 0), 3));
  if (this->GetSettings().CsgOperation != value)
  {
    this->GetSettings().CsgOperation = value;
    this->Modified();
  }
}

int vtkWalkOnSpheresSolverDriver::GetCsgOperation()
{
  return gridfree::CodeOf(this->GetSettings().CsgOperation);
}

GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolverDriver, SourceExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolverDriver, DiffusionExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolverDriver, AbsorptionExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolverDriver, BoundaryValueExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolverDriver, BoundaryLaplacianExpression)
GRIDFREE_IMPLICIT_BOUNDARY_ACCESSORS(vtkWalkOnSpheresSolverDriver)

vtkPolyData* vtkWalkOnSpheresSolverDriver::GetOutput()
{
  return this->GetOutput(0);
}

vtkPolyData* vtkWalkOnSpheresSolverDriver::GetOutput(int port)
{
  return vtkPolyData::SafeDownCast(this->GetOutputDataObject(port));
}

int vtkWalkOnSpheresSolverDriver::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
  return 1;
}

int vtkWalkOnSpheresSolverDriver::RequestDataObject(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    if (!vtkPolyData::SafeDownCast(info->Get(vtkDataObject::DATA_OBJECT())))
    {
      vtkNew<vtkPolyData> output;
      info->Set(vtkDataObject::DATA_OBJECT(), output);
    }
  }
  return 1;
}

// Editing the implicit function must re-execute the filter.
vtkMTimeType vtkWalkOnSpheresSolverDriver::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->GetSettings().ImplicitBoundary)
  {
    time = std::max(time, this->GetSettings().ImplicitBoundary->GetMTime());
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
  return this->BuildKeptProblem(
    0, this->GetSettings(), gridfree::ArraySelections::Of(this), data, state.Problem);
}

// One batch at `points`, by `estimate` (into arrays or numbers), with
// this filter's progress and its distinct warnings kept for ReportWarnings.
bool vtkWalkOnSpheresSolverDriver::RunBatch(
  const std::function<bool(const gridfree::PointEstimateRun&, gridfree::PointEstimateSummary&)>&
    estimate,
  double progress, double& seconds, vtkIdType& walks)
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
    completed = estimate(run, summary);
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

bool vtkWalkOnSpheresSolverDriver::EstimateAt(const std::vector<std::array<double, 3>>& points,
  vtkPointData* arrays, double progress, double& seconds, vtkIdType& walks,
  gridfree::EstimateArrays* found)
{
  return this->RunBatch(
    [&](const gridfree::PointEstimateRun& run, gridfree::PointEstimateSummary& summary) {
      return gridfree::EstimateAtPoints(this, this->Internal->Problem, this->GetSettings(),
        points, arrays, nullptr, run, summary, found);
    },
    progress, seconds, walks);
}

bool vtkWalkOnSpheresSolverDriver::EstimateNumbersAt(
  const std::vector<std::array<double, 3>>& points, gridfree::PointNumbers& estimates,
  double progress, double& seconds, vtkIdType& walks)
{
  return this->RunBatch(
    [&](const gridfree::PointEstimateRun& run, gridfree::PointEstimateSummary& summary) {
      return gridfree::EstimateNumbersAtPoints(
        this, this->Internal->Problem, this->GetSettings(), points, estimates, run, summary);
    },
    progress, seconds, walks);
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
  const gridfree::SolveSettings& s = this->GetSettings();
  gridfree::PrintProblemSettings(os, indent, s);
}
