// Asks a built problem (GridFreeProblemBuilder) for its estimates at a list
// of points and lays them out as VTK arrays (GridFreeEstimateArrays.h), with
// the batch's warnings (GridFreeEstimateWarnings.h), named as the solver's
// output:
// `T`, `T_Variance` (and the biharmonic `T_Laplacian`), the walk counters,
// `BoundaryDistance`, `T_ClosestBoundaryValue` and the derivative arrays,
// with the run's summary in field data. vtkWalkOnSpheresSolver fills its
// output with it; the stream tracer, the adaptive sampler and the
// application filters call it on the points they choose, with no internal
// pipeline. Progress is reported and abort checked on `reporter`.
// Private to the GridFree::Filters module.
#ifndef GridFreePointEstimates_h
#define GridFreePointEstimates_h

#include "vtkType.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataSet;
class vtkPointData;
class vtkFieldData;

namespace gridfree
{
class RunningSumsCache;
struct BuiltProblem;
struct EstimateArrays;
struct PointNumbers;
struct SolveSettings;

struct PointEstimateRun
{
  // Progress of this batch as the part [begin, end] of the reporter's.
  double ProgressBegin = 0.0;
  double ProgressEnd = 1.0;
  // Running sums to continue from and keep (progressive refinement); null
  // for a fresh batch.
  RunningSumsCache* Kept = nullptr;
  // Receives each warning (the solver reports it at once; filters that run
  // many batches report each distinct one once).
  std::function<void(const std::string&)> Warn;
  // Warn when the batch is projected to take long (not under a time budget,
  // which bounds it).
  bool AnnounceLongSolves = true;
  // Warn about points short of the target standard error (a time budget
  // says it for the whole solve instead).
  bool ReportShortOfTarget = true;
  // Warn about points whose error bar cannot be trusted (the application
  // filters' inner solves do not: their outputs are not these estimates).
  bool ReportUnreliableErrorBars = true;
  // A cache estimator keeps a cache grown past the walks asked for (the
  // rounds of a time budget) rather than building a fresh one.
  bool KeepGrownCaches = false;
};

struct PointEstimateSummary
{
  bool Completed = false; // false when aborted
  std::uint64_t WalksRun = 0;
  double Seconds = 0.0;
  int ResumedWalksPerPoint = 0;
  // Target-error mode: points that took every walk allowed with a standard
  // error still above the target.
  std::int64_t PointsShortOfTarget = 0;
  // Points whose error bar cannot be trusted (ErrorBarReliability.h).
  std::int64_t UnreliableErrorBars = 0;
  // Points that ran all their walks (all of them unless aborted), and,
  // after an abort, those that hold no walks at all (NaN).
  std::int64_t PointsFinished = 0;
  std::int64_t PointsWithoutWalks = 0;
};

// The coordinates of `data`'s points, in order.
std::vector<std::array<double, 3>> PointsOf(vtkDataSet* data);

// Estimates at `points` with `settings`' walks, seed, threads and
// derivatives, and adds the arrays to `arrays` (and the summary to
// `fieldData`, unless null); `keep`, when given, holds them too, to be read
// by member. False when aborted.
bool EstimateAtPoints(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, const std::vector<std::array<double, 3>>& points,
  vtkPointData* arrays, vtkFieldData* fieldData, const PointEstimateRun& run,
  PointEstimateSummary& summary, EstimateArrays* keep = nullptr);

// The same batch for a filter that uses the numbers itself (the stream
// tracer): the core's collected estimates (Problem::EstimateAll) with each
// point's distance to the boundary (GridFreePointNumbers.h), with the same
// warnings; nothing goes to an output.
bool EstimateNumbersAtPoints(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, const std::vector<std::array<double, 3>>& points,
  PointNumbers& numbers, const PointEstimateRun& run, PointEstimateSummary& summary);
} // namespace gridfree

#endif
