/**
 * @class   vtkWalkOnSpheresSolverDriver
 * @brief   Base of filters that run an internal vtkWalkOnSpheresSolver on
 *          points they choose themselves (the stream tracer's integrator
 *          points, the adaptive sampler's samples).
 *
 * Input 0 ("Boundary") and input 2 ("Source", optional) are handed to the
 * solver as they are; input 1 is the subclass's own (seeds, candidate
 * points). The solver's boundary array is the one selected on this filter
 * with SetInputArrayToProcess(0, ...) (and 1, 2 for the biharmonic and
 * source arrays). GetSolver() configures everything else; the most used
 * settings have shortcuts here, for ParaView's panels. Every input is
 * requested whole.
 *
 * @sa vtkWalkOnSpheresStreamTracer vtkWalkOnSpheresAdaptiveSampler
 */
#ifndef vtkWalkOnSpheresSolverDriver_h
#define vtkWalkOnSpheresSolverDriver_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class vtkAlgorithmOutput;
class vtkDataObject;
class vtkWalkOnSpheresSolver;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresSolverDriver : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkWalkOnSpheresSolverDriver, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The solver's inputs: Boundary (port 0) and Source (port 2).
   */
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkDataObject* data);
  ///@}

  /**
   * The internal solver. Set its equation, walks, epsilon, seed, threads,
   * implicit boundary... here; its inputs and gradient settings are managed
   * by the filter.
   */
  vtkWalkOnSpheresSolver* GetSolver() { return this->Solver; }

  ///@{
  /**
   * Shortcuts to the internal solver's most used settings.
   */
  void SetWalksPerPoint(int walks);
  int GetWalksPerPoint();
  void SetEpsilon(double epsilon);
  double GetEpsilon();
  void SetSeed(int seed);
  int GetSeed();
  void SetNumberOfThreads(int threads);
  int GetNumberOfThreads();
  void SetEquation(int equation);
  int GetEquation();
  ///@}

protected:
  vtkWalkOnSpheresSolverDriver();
  ~vtkWalkOnSpheresSolverDriver() override;

  static constexpr int BoundaryPort = 0;
  static constexpr int SourcePort = 2;

  vtkMTimeType GetMTime() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Hands the Boundary and Source inputs and this filter's array selections
  // to the solver, and turns its gradient on.
  void ConnectSolver(vtkDataObject* boundary, vtkDataObject* source);

  vtkWalkOnSpheresSolver* Solver; // owned

private:
  vtkWalkOnSpheresSolverDriver(const vtkWalkOnSpheresSolverDriver&) = delete;
  void operator=(const vtkWalkOnSpheresSolverDriver&) = delete;
};

#endif
