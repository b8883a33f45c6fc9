/**
 * @class   vtkPWalkOnSpheresSolver
 * @brief   vtkWalkOnSpheresSolver for distributed runs: gathers the boundary
 *          and source from every rank
 *
 * In a distributed run (`mpirun -np N pvbatch`, a pvserver with N ranks)
 * every rank holds a piece of each input, but a walk may reach any part of
 * the boundary and of the source. With a Controller of more than one process
 * this solver asks its Boundary and Source upstreams for this rank's piece,
 * gathers every rank's pieces (merged in rank order, so a dataset split into
 * pieces gives the serial numbers bit for bit) and solves this rank's piece
 * of the probe. Executing it is then a collective operation that every rank
 * must join. Field data `BoundaryPiecesGathered` and `SourcePiecesGathered`
 * count the ranks whose pieces were merged (empty pieces and copies of a
 * lower rank's piece, from an upstream that ignores piece requests, are
 * left out). With one process, or no controller, it is a
 * vtkWalkOnSpheresSolver. The ParaView plugin's solver is this class.
 *
 * @sa vtkWalkOnSpheresSolver vtkPProbeFilter
 */
#ifndef vtkPWalkOnSpheresSolver_h
#define vtkPWalkOnSpheresSolver_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresSolver.h"

class vtkMultiProcessController;

class GRIDFREEFILTERS_EXPORT vtkPWalkOnSpheresSolver : public vtkWalkOnSpheresSolver
{
public:
  static vtkPWalkOnSpheresSolver* New();
  vtkTypeMacro(vtkPWalkOnSpheresSolver, vtkWalkOnSpheresSolver);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The controller of the distributed run (default: the global controller,
   * so under `mpirun pvbatch` or a pvserver with several ranks every rank
   * takes part). With nullptr or one process nothing is gathered.
   */
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

protected:
  vtkPWalkOnSpheresSolver();
  ~vtkPWalkOnSpheresSolver() override;

  bool GatherInputs(vtkDataObject* boundary, vtkDataObject* source,
    vtkWalkOnSpheresSolverPieces& pieces) override;
  void RequestSharedInput(vtkInformation* info) override;

  // True when the inputs are gathered from the ranks of Controller.
  bool Distributed() const;

  vtkMultiProcessController* Controller = nullptr;

private:
  vtkPWalkOnSpheresSolver(const vtkPWalkOnSpheresSolver&) = delete;
  void operator=(const vtkPWalkOnSpheresSolver&) = delete;
};

#endif
