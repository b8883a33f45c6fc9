#include "vtkWalkOnSpheresProbeAlgorithm.h"

#include "GridFreeArrays.h"
#include "GridFreeMessageCollector.h"
#include "GridFreeWholeInputRequest.h"
#include "vtkCallbackCommand.h"
#include "vtkDataObject.h"
#include "vtkDataObjectTypes.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkWalkOnSpheresSolver.h"

vtkWalkOnSpheresProbeAlgorithm::vtkWalkOnSpheresProbeAlgorithm()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
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

void vtkWalkOnSpheresProbeAlgorithm::ConfigureSolver(vtkWalkOnSpheresSolver* solver)
{
  solver->SetWalksPerPoint(this->WalksPerPoint);
  solver->SetEpsilon(this->Epsilon);
  solver->SetEpsilonIsRelative(this->EpsilonIsRelative);
  solver->SetMaxSteps(this->MaxSteps);
  solver->SetSeed(this->Seed);
  solver->SetNumberOfThreads(this->NumberOfThreads);
}

namespace
{
// Relays an internal solver's progress into a range of the owner's, and the
// owner's abort into the solver (which checks it at every progress report).
struct ProgressRelay
{
  vtkWalkOnSpheresProbeAlgorithm* Owner;
  vtkWalkOnSpheresSolver* Solver;
  double Begin, End;
  bool Aborted = false;

  static void Callback(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* relay = static_cast<ProgressRelay*>(clientData);
    const double fraction = callData ? *static_cast<double*>(callData) : 0.0;
    relay->Owner->UpdateProgress(relay->Begin + (relay->End - relay->Begin) * fraction);
    if (relay->Owner->CheckAbort())
    {
      relay->Aborted = true;
      relay->Solver->SetAbortExecute(1);
    }
  }
};
} // namespace

bool vtkWalkOnSpheresProbeAlgorithm::RunSolver(
  vtkWalkOnSpheresSolver* solver, double begin, double end, bool& aborted)
{
  ProgressRelay relay{ this, solver, begin, end };
  vtkNew<vtkCallbackCommand> progress;
  progress->SetCallback(&ProgressRelay::Callback);
  progress->SetClientData(&relay);
  vtkNew<gridfree::MessageCollector> errors, warnings;
  const unsigned long progressTag = solver->AddObserver(vtkCommand::ProgressEvent, progress);
  const unsigned long errorTag = solver->AddObserver(vtkCommand::ErrorEvent, errors);
  const unsigned long warningTag = solver->AddObserver(vtkCommand::WarningEvent, warnings);
  solver->Update();
  solver->RemoveObserver(progressTag);
  solver->RemoveObserver(errorTag);
  solver->RemoveObserver(warningTag);

  this->LastNumberOfWalks += solver->GetLastNumberOfWalks();
  this->LastSolveSeconds += solver->GetLastSolveSeconds();
  for (const std::string& message : warnings->Messages)
  {
    vtkWarningMacro(<< message);
  }
  aborted = relay.Aborted || this->CheckAbort();
  if (!errors->Text.empty())
  {
    vtkErrorMacro(<< errors->Text);
    return false;
  }
  return !aborted;
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
  os << indent << "WalksPerPoint: " << this->WalksPerPoint << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "EpsilonIsRelative: " << this->EpsilonIsRelative << "\n";
  os << indent << "MaxSteps: " << this->MaxSteps << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastNumberOfWalks: " << this->LastNumberOfWalks << "\n";
  os << indent << "LastSolveSeconds: " << this->LastSolveSeconds << "\n";
}
