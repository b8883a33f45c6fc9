#include "vtkPWalkOnSpheresSolver.h"

#include "GridFreePieceGather.h"
#include "GridFreeWholeInputRequest.h"

#include "vtkDataObject.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkPWalkOnSpheresSolver);
vtkCxxSetObjectMacro(vtkPWalkOnSpheresSolver, Controller, vtkMultiProcessController);

vtkPWalkOnSpheresSolver::vtkPWalkOnSpheresSolver()
{
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

vtkPWalkOnSpheresSolver::~vtkPWalkOnSpheresSolver()
{
  this->SetController(nullptr);
}

bool vtkPWalkOnSpheresSolver::Distributed() const
{
  return this->Controller && this->Controller->GetNumberOfProcesses() > 1;
}

void vtkPWalkOnSpheresSolver::RequestSharedInput(vtkInformation* info)
{
  if (this->Distributed())
  {
    gridfree::RequestPiece(
      info, this->Controller->GetLocalProcessId(), this->Controller->GetNumberOfProcesses());
  }
  else
  {
    this->Superclass::RequestSharedInput(info);
  }
}

bool vtkPWalkOnSpheresSolver::GatherInputs(
  vtkDataObject* boundary, vtkDataObject* source, vtkWalkOnSpheresSolverPieces& pieces)
{
  if (!this->Distributed())
  {
    return this->Superclass::GatherInputs(boundary, source, pieces);
  }
  pieces.Distributed = true;
  // Port 0 is the Boundary, port 2 the Source; an unconnected port is the
  // same on every rank, so every rank skips the same exchanges.
  for (int port : { 0, 2 })
  {
    if (this->GetNumberOfInputConnections(port) == 0)
    {
      continue;
    }
    std::string reason;
    gridfree::GatheredPieces& gathered = port == 0 ? pieces.Boundary : pieces.Source;
    if (!gridfree::GatherPieces(this->Controller, port == 0 ? boundary : source, gathered, reason))
    {
      vtkErrorMacro(<< "Cannot gather the " << (port == 0 ? "Boundary" : "Source")
                    << " input from the " << this->Controller->GetNumberOfProcesses()
                    << " ranks: " << reason << ".");
      return false;
    }
  }
  return true;
}

void vtkPWalkOnSpheresSolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Controller: " << this->Controller << "\n";
}
