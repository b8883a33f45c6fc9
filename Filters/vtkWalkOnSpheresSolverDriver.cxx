#include "vtkWalkOnSpheresSolverDriver.h"

#include "GridFreeWholeInputRequest.h"

#include "vtkWalkOnSpheresSolver.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>

vtkWalkOnSpheresSolverDriver::vtkWalkOnSpheresSolverDriver()
  : Solver(vtkWalkOnSpheresSolver::New())
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(1);
  // Every run has new points. The internal solver is a plain
  // vtkWalkOnSpheresSolver, which never gathers: it works on this filter's
  // whole inputs, on this rank alone.
  this->Solver->SetKeepRunningSums(false);
}

vtkWalkOnSpheresSolverDriver::~vtkWalkOnSpheresSolverDriver()
{
  this->Solver->Delete();
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

void vtkWalkOnSpheresSolverDriver::SetWalksPerPoint(int walks)
{
  this->Solver->SetWalksPerPoint(walks);
}
int vtkWalkOnSpheresSolverDriver::GetWalksPerPoint()
{
  return this->Solver->GetWalksPerPoint();
}
void vtkWalkOnSpheresSolverDriver::SetEpsilon(double epsilon)
{
  this->Solver->SetEpsilon(epsilon);
}
double vtkWalkOnSpheresSolverDriver::GetEpsilon()
{
  return this->Solver->GetEpsilon();
}
void vtkWalkOnSpheresSolverDriver::SetSeed(int seed)
{
  this->Solver->SetSeed(seed);
}
int vtkWalkOnSpheresSolverDriver::GetSeed()
{
  return this->Solver->GetSeed();
}
void vtkWalkOnSpheresSolverDriver::SetNumberOfThreads(int threads)
{
  this->Solver->SetNumberOfThreads(threads);
}
int vtkWalkOnSpheresSolverDriver::GetNumberOfThreads()
{
  return this->Solver->GetNumberOfThreads();
}
void vtkWalkOnSpheresSolverDriver::SetEquation(int equation)
{
  this->Solver->SetEquation(equation);
}
int vtkWalkOnSpheresSolverDriver::GetEquation()
{
  return this->Solver->GetEquation();
}

vtkMTimeType vtkWalkOnSpheresSolverDriver::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->Solver->GetMTime());
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

void vtkWalkOnSpheresSolverDriver::ConnectSolver(vtkDataObject* boundary, vtkDataObject* source)
{
  vtkWalkOnSpheresSolver* solver = this->Solver;
  solver->SetInputData(0, boundary);
  solver->SetInputData(2, source);
  for (int index = 0; index < 3; ++index)
  {
    if (vtkInformation* selection = this->GetInputArrayInformation(index))
    {
      if (selection->Has(vtkDataObject::FIELD_NAME()) ||
        selection->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE()))
      {
        solver->SetInputArrayToProcess(index, selection);
      }
    }
  }
  solver->ComputeGradientOn();
}

void vtkWalkOnSpheresSolverDriver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Solver:\n";
  this->Solver->PrintSelf(os, indent.GetNextIndent());
}
