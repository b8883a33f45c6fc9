// Builds the core problem (gridfree::Problem: boundary with its hierarchy
// and values, equation, sources, walk settings) from a filter's VTK inputs,
// settings and array selections, and keeps the built boundary: a build whose
// boundary inputs and boundary-shaping settings did not change reuses it,
// so moving the probe, raising the walks or refining never rebuilds the
// hierarchy. Every filter that estimates owns one: vtkWalkOnSpheresSolver,
// the stream tracer, the adaptive sampler and the application filters,
// which then ask the problem directly (GridFreePointEstimates), with no
// internal pipeline. Errors and warnings are reported as `reporter`'s.
// Private to the GridFree::Filters module.
#ifndef GridFreeProblemBuilder_h
#define GridFreeProblemBuilder_h

#include "GridFreeArraySelection.h"
#include "GridFreeSolveSettings.h"

#include <gridfree/problem/Problem.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

class vtkDataObject;
class vtkDataSet;
class vtkObject;

namespace gridfree
{
struct CacheSlot;

// A problem ready to answer batches, and how its results are named.
struct BuiltProblem
{
  int Dimension = 3;
  std::shared_ptr<const Problem<2>> Problem2;
  std::shared_ptr<const Problem<3>> Problem3;
  std::string Name = "Solution"; // of the solution arrays (the boundary array's name)
  int Components = 1;            // of the solution (g's; h's are as many)
  bool Biharmonic = false;
  // The solution caches of this problem, shared with the problems built
  // before from the same data and settings (GridFreeCacheSlot.h); null for
  // the pointwise estimator.
  std::shared_ptr<CacheSlot> Caches;
  // max - min of the boundary values g over their components (NaN when g is
  // given by expressions only): what a relative target error refers to.
  double ValueRange = 0.0;

  template <int DIM>
  const Problem<DIM>& Get() const
  {
    if constexpr (DIM == 2)
    {
      return *this->Problem2;
    }
    else
    {
      return *this->Problem3;
    }
  }
};

// The data a problem is built from.
struct ProblemData
{
  vtkDataObject* Boundary = nullptr; // whole (gathered in a distributed run)
  // The Boundary as this rank received it and the signature of the pieces
  // gathered from other ranks (0 in a serial run): what the cache is keyed on.
  vtkDataObject* BoundaryPiece = nullptr;
  std::uint64_t GatheredSignature = 0;
  vtkDataObject* Source = nullptr;
  // The points the problem will be asked about (at least their bounds):
  // implicit and CSG boundaries are built in a region around them.
  vtkDataSet* Region = nullptr;
};

class ProblemBuilder
{
public:
  ProblemBuilder();
  ~ProblemBuilder();
  ProblemBuilder(const ProblemBuilder&) = delete;
  ProblemBuilder& operator=(const ProblemBuilder&) = delete;

  // Checks the inputs and settings and resolves the arrays; false after an
  // error. The problem itself is made by Build.
  bool Resolve(vtkObject* reporter, const SolveSettings& settings,
    const ArraySelections& arrays, const ProblemData& data);
  // The problem of the last successful Resolve (the boundary reused when
  // its key is unchanged); false after an error.
  bool Build(vtkObject* reporter, BuiltProblem& problem);
  // Both.
  bool Build(vtkObject* reporter, const SolveSettings& settings, const ArraySelections& arrays,
    const ProblemData& data, BuiltProblem& problem)
  {
    return this->Resolve(reporter, settings, arrays, data) && this->Build(reporter, problem);
  }

  // Whether the last Build built the boundary (false: reused).
  bool GetLastBoundaryBuilt() const { return this->LastBoundaryBuilt; }
  // Whether the last Build failed because the filter's Abort stopped the
  // preparation of the varying coefficients (a warning, not an error, was
  // reported).
  bool GetLastBuildAborted() const { return this->LastBuildAborted; }
  // Frees the kept boundary.
  void Forget();

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
  bool LastBoundaryBuilt = false;
  bool LastBuildAborted = false;
};
} // namespace gridfree

#endif
