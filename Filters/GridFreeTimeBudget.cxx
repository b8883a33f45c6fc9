#include "GridFreeTimeBudget.h"

#include "GridFreeArrays.h"
#include "GridFreeSolveSettings.h"

#include "vtkAlgorithm.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <gridfree/statistics/RunningSumsCache.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <string>
#include <vector>

namespace gridfree
{
bool EstimateWithinTimeBudget(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, double budgetSeconds,
  const std::vector<std::array<double, 3>>& points, vtkPointData* arrays,
  vtkFieldData* fieldData, const PointEstimateRun& run, PointEstimateSummary& summary,
  TimeBudgetSummary& budget)
{
  summary = PointEstimateSummary();
  budget = TimeBudgetSummary();
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const int most = std::max(2, settings.WalksPerPoint);
  const bool target = settings.TargetStandardError > 0.0;
  // The first round continues from sums kept by an earlier solve, if any.
  const int kept = run.Kept && run.Kept->KeptWalks() <= static_cast<std::uint64_t>(most)
    ? static_cast<int>(run.Kept->KeptWalks())
    : 0;
  int walks = std::min(most, std::max(kFirstBudgetRoundWalks, kept));

  // Each round's warnings replace the last one's: the last round's are
  // reported (the earlier rounds' counts are no longer the result's).
  std::vector<std::string> warnings;
  PointEstimateRun round = run;
  round.AnnounceLongSolves = false;
  round.ReportShortOfTarget = false;
  round.KeepGrownCaches = true;
  round.Warn = [&warnings](const std::string& text) {
    if (std::find(warnings.begin(), warnings.end(), text) == warnings.end())
    {
      warnings.push_back(text);
    }
  };
  // Each round starts from the probe's own arrays: the last round's
  // solution arrays would otherwise look like probe arrays of the same name.
  vtkNew<vtkPointData> probeArrays;
  vtkNew<vtkFieldData> probeFields;
  if (arrays)
  {
    probeArrays->ShallowCopy(arrays);
  }
  if (fieldData)
  {
    probeFields->ShallowCopy(fieldData);
  }
  const double span = run.ProgressEnd - run.ProgressBegin;
  double projected = budgetSeconds;
  bool completed = true;
  std::uint64_t walksRun = 0;
  while (true)
  {
    SolveSettings roundSettings = settings;
    roundSettings.WalksPerPoint = walks;
    // A cache grows with the rounds too: its walks per sphere (per boundary
    // cache point) at least a point's.
    roundSettings.WalksPerSphere = std::max(settings.WalksPerSphere, walks);
    roundSettings.WalksPerCachePoint = std::max(settings.WalksPerCachePoint, walks);
    const double now = elapsed();
    round.ProgressBegin = run.ProgressBegin + span * std::min(1.0, now / budgetSeconds);
    round.ProgressEnd = run.ProgressBegin + span * std::min(1.0, (now + projected) / budgetSeconds);
    round.ProgressEnd = std::max(round.ProgressEnd, round.ProgressBegin);
    warnings.clear();
    if (budget.Rounds > 0)
    {
      if (arrays)
      {
        arrays->ShallowCopy(probeArrays);
      }
      if (fieldData)
      {
        fieldData->ShallowCopy(probeFields);
      }
    }
    PointEstimateSummary one;
    completed = EstimateAtPoints(
      reporter, problem, roundSettings, points, arrays, fieldData, round, one);
    budget.Rounds += 1;
    budget.WalksPerPointReached = walks;
    walksRun += one.WalksRun;
    if (budget.Rounds == 1)
    {
      summary.ResumedWalksPerPoint = one.ResumedWalksPerPoint;
    }
    summary.PointsShortOfTarget = one.PointsShortOfTarget;
    summary.UnreliableErrorBars = one.UnreliableErrorBars;
    if (!completed || walks >= most || (target && one.PointsShortOfTarget == 0))
    {
      break;
    }
    // The next round runs the walks between this count and twice it, for
    // every point (or those still above the target), at the rate so far.
    const int next = walks > most / 2 ? most : 2 * walks;
    const double spent = elapsed();
    const double walking = target ? static_cast<double>(one.PointsShortOfTarget)
                                  : static_cast<double>(points.size());
    const double rate = spent > 0.0 ? static_cast<double>(walksRun) / spent : 0.0;
    // No walk run yet (all taken from kept sums): no rate to project with,
    // and the next round is the one that measures it.
    projected = rate > 0.0 ? walking * static_cast<double>(next - walks) / rate : 0.0;
    if (walksRun > 0 && spent + projected > budgetSeconds)
    {
      break;
    }
    walks = next;
  }
  summary.Completed = completed;
  summary.WalksRun = walksRun;
  summary.Seconds = elapsed();
  for (const std::string& text : warnings)
  {
    run.Warn(text);
  }
  if (!completed)
  {
    return false;
  }

  // Every point took the last round's walks, or (with a target) the
  // WalkCount EstimateAtPoints wrote.
  if (arrays && !target)
  {
    auto count = vtkSmartPointer<vtkIntArray>::New();
    count->SetName("WalkCount");
    count->SetNumberOfTuples(static_cast<vtkIdType>(points.size()));
    count->Fill(walks);
    arrays->AddArray(count);
  }
  if (fieldData)
  {
    // The whole solve's figures, not the last round's.
    AddFieldValue(fieldData, "SolveSeconds", summary.Seconds);
    AddFieldValue(fieldData, "WalksRun", static_cast<double>(walksRun));
    AddFieldValue(fieldData, "WalksPerSecond",
      summary.Seconds > 0.0 ? static_cast<double>(walksRun) / summary.Seconds : 0.0);
    AddFieldValue(
      fieldData, "ResumedWalksPerPoint", static_cast<double>(summary.ResumedWalksPerPoint));
    AddFieldValue(fieldData, "TimeBudgetSeconds", budgetSeconds);
    AddFieldValue(fieldData, "WalksPerPointReached", static_cast<double>(walks));
  }
  if (target && summary.PointsShortOfTarget > 0 && run.Warn)
  {
    std::ostringstream msg;
    msg << summary.PointsShortOfTarget << " of " << points.size()
        << " probe points are above the target standard error when the time budget of "
        << budgetSeconds << " s stopped the walks at " << walks << " walks per point"
        << (walks < most ? "" : " (Walks Per Point, the most a point may take)")
        << ": raise the time budget"
        << (walks < most ? "" : " and Walks Per Point") << ", or the target.";
    run.Warn(msg.str());
  }
  return true;
}
} // namespace gridfree
