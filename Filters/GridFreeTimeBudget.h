// The solver's Time Budget: estimates at a list of points in rounds of
// doubling walk counts, each continuing from the running sums of the one
// before (progressive refinement), until WalksPerPoint is reached, every
// point is at the target standard error (target-error mode), or the next
// round would not fit in the time left. The result is that of one solve
// with the last round's count: which count the budget reaches depends on the
// machine's speed, the numbers at that count do not.
// Private to the GridFree::Filters module.
#ifndef GridFreeTimeBudget_h
#define GridFreeTimeBudget_h

#include "GridFreePointEstimates.h"

namespace gridfree
{
struct TimeBudgetSummary
{
  int Rounds = 0;
  // The walks per point of the last round (at most, with a target).
  int WalksPerPointReached = 0;
};

// Walks of the first round (fewer if WalksPerPoint is smaller): the
// target-error mode's first check.
constexpr int kFirstBudgetRoundWalks = 128;

// Runs the rounds within `budgetSeconds` (the first always runs) with
// `run.Kept` (required) holding the sums between them, and adds the arrays
// and field data of EstimateAtPoints, plus WalkCount, WalksPerPointReached
// and TimeBudgetSeconds; `summary` covers all rounds. False when aborted.
bool EstimateWithinTimeBudget(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, double budgetSeconds,
  const std::vector<std::array<double, 3>>& points, vtkPointData* arrays,
  vtkFieldData* fieldData, const PointEstimateRun& run, PointEstimateSummary& summary,
  TimeBudgetSummary& budget);
} // namespace gridfree

#endif
