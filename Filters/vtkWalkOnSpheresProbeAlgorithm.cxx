#include "vtkWalkOnSpheresProbeAlgorithm.h"

#include "GridFreeArraySelection.h"
#include "GridFreeArrays.h"
#include "GridFreePointEstimates.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"
#include "GridFreeWholeInputRequest.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDataObjectTypes.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <array>
#include <exception>
#include <string>
#include <vector>

vtkWalkOnSpheresProbeAlgorithm::vtkWalkOnSpheresProbeAlgorithm()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
  this->GetSettings().WalksPerPoint = 256;
}

vtkWalkOnSpheresProbeAlgorithm::~vtkWalkOnSpheresProbeAlgorithm() = default;

void vtkWalkOnSpheresProbeAlgorithm::SetBoundaryConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(BoundaryPort, output);
}

void vtkWalkOnSpheresProbeAlgorithm::SetBoundaryData(vtkDataObject* data)
{
  this->SetInputData(BoundaryPort, data);
}

void vtkWalkOnSpheresProbeAlgorithm::SetProbeConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(ProbePort, output);
}

void vtkWalkOnSpheresProbeAlgorithm::SetProbeData(vtkDataObject* data)
{
  this->SetInputData(ProbePort, data);
}

int vtkWalkOnSpheresProbeAlgorithm::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == BoundaryPort)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    if (port != ProbePort)
    {
      info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    }
  }
  return 1;
}

int vtkWalkOnSpheresProbeAlgorithm::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkDataSet" : "vtkPolyData");
  return 1;
}

int vtkWalkOnSpheresProbeAlgorithm::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    vtkDataObject* output = outInfo->Get(vtkDataObject::DATA_OBJECT());
    std::string type;
    if (port == 0)
    {
      vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
      if (!probe)
      {
        continue; // reported in RequestData
      }
      type = probe->GetClassName();
    }
    else
    {
      type = this->GetOutputPortInformation(port)->Get(vtkDataObject::DATA_TYPE_NAME());
    }
    if (!output || !output->IsA(type.c_str()))
    {
      vtkDataObject* fresh = vtkDataObjectTypes::NewDataObject(type.c_str());
      if (!fresh)
      {
        vtkErrorMacro(<< "Cannot make an output of type " << type << ".");
        return 0;
      }
      outInfo->Set(vtkDataObject::DATA_OBJECT(), fresh);
      fresh->FastDelete();
    }
  }
  return 1;
}

// Structured probes (images) keep their extent.
int vtkWalkOnSpheresProbeAlgorithm::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* probeInfo = inputVector[ProbePort]->GetInformationObject(0);
  if (!probeInfo)
  {
    return 1;
  }
  if (probeInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(),
      probeInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  else
  {
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  }
  return 1;
}

int vtkWalkOnSpheresProbeAlgorithm::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  for (int port = 0; port < this->GetNumberOfInputPorts(); ++port)
  {
    vtkInformation* info = inputVector[port]->GetInformationObject(0);
    if (port != ProbePort)
    {
      gridfree::RequestWholeInput(info);
    }
    else if (info)
    {
      info->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
      info->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
      info->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS());
      info->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
    }
  }
  return 1;
}

bool vtkWalkOnSpheresProbeAlgorithm::RunSolve(const gridfree::SolveSettings& settings,
  const gridfree::ArraySelections& arrays, vtkDataObject* boundary, vtkDataObject* source,
  vtkDataSet* probe, double begin, double end, bool& aborted, int problemNumber,
  const BatchRunner& estimate)
{
  aborted = false;
  gridfree::ProblemData data;
  data.Boundary = boundary;
  data.BoundaryPiece = boundary;
  data.Source = source;
  data.Region = probe;
  gridfree::BuiltProblem problem;
  if (!this->BuildKeptProblem(problemNumber, settings, arrays, data, problem))
  {
    return false;
  }
  const std::vector<std::array<double, 3>> points = gridfree::PointsOf(probe);
  std::vector<std::string> warnings;
  gridfree::PointEstimateRun run;
  run.ProgressBegin = begin;
  run.ProgressEnd = end;
  run.ReportUnreliableErrorBars = false;
  run.Warn = [&warnings](const std::string& text) {
    if (std::find(warnings.begin(), warnings.end(), text) == warnings.end())
    {
      warnings.push_back(text);
    }
  };
  gridfree::PointEstimateSummary summary;
  bool completed = false;
  try
  {
    completed = estimate(problem, points, run, summary);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Walk on spheres failed: " << e.what());
    return false;
  }
  this->LastNumberOfWalks += static_cast<vtkIdType>(summary.WalksRun);
  this->LastSolveSeconds += summary.Seconds;
  for (const std::string& message : warnings)
  {
    vtkWarningMacro(<< message);
  }
  aborted = !completed || this->CheckAbort();
  return !aborted;
}

bool vtkWalkOnSpheresProbeAlgorithm::Solve(const gridfree::SolveSettings& settings,
  const gridfree::ArraySelections& arrays, vtkDataObject* boundary, vtkDataObject* source,
  vtkDataSet* probe, double begin, double end, vtkSmartPointer<vtkDataSet>& result,
  bool& aborted, int problemNumber)
{
  return this->RunSolve(settings, arrays, boundary, source, probe, begin, end, aborted,
    problemNumber,
    [&](const gridfree::BuiltProblem& problem, const std::vector<std::array<double, 3>>& points,
      const gridfree::PointEstimateRun& run, gridfree::PointEstimateSummary& summary) {
      // The probe with the solution arrays, as vtkWalkOnSpheresSolver's output.
      result.TakeReference(probe->NewInstance());
      result->CopyStructure(probe);
      result->GetPointData()->PassData(probe->GetPointData());
      result->GetCellData()->PassData(probe->GetCellData());
      result->GetFieldData()->PassData(probe->GetFieldData());
      return gridfree::EstimateAtPoints(this, problem, settings, points, result->GetPointData(),
        result->GetFieldData(), run, summary);
    });
}

bool vtkWalkOnSpheresProbeAlgorithm::SolveNumbers(const gridfree::SolveSettings& settings,
  const gridfree::ArraySelections& arrays, vtkDataObject* boundary, vtkDataObject* source,
  vtkDataSet* where, double begin, double end, gridfree::PointNumbers& found, bool& aborted,
  int problemNumber)
{
  return this->RunSolve(settings, arrays, boundary, source, where, begin, end, aborted,
    problemNumber,
    [&](const gridfree::BuiltProblem& problem, const std::vector<std::array<double, 3>>& points,
      const gridfree::PointEstimateRun& run, gridfree::PointEstimateSummary& summary) {
      return gridfree::EstimateNumbersAtPoints(this, problem, settings, points, found, run,
        summary);
    });
}

void vtkWalkOnSpheresProbeAlgorithm::AddSummary(vtkDataObject* output)
{
  gridfree::AddFieldValue(
    output->GetFieldData(), "TotalWalks", static_cast<double>(this->LastNumberOfWalks));
  gridfree::AddFieldValue(output->GetFieldData(), "SolveSeconds", this->LastSolveSeconds);
}

void vtkWalkOnSpheresProbeAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastNumberOfWalks: " << this->LastNumberOfWalks << "\n";
  os << indent << "LastSolveSeconds: " << this->LastSolveSeconds << "\n";
}
