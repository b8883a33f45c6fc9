#include "GridFreePointEstimates.h"

#include "GridFreeArrays.h"
#include "GridFreeDerivativeArrays.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"

#include <gridfree/problem/Problem.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "vtkAlgorithm.h"
#include "vtkDataSet.h"
#include "vtkPointData.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkFieldData.h"
#include "vtkOutputWindow.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

namespace gridfree
{
namespace
{
// A batch projected (after kRateSeconds of measuring) to take longer than
// kLongSolveSeconds is announced with a warning.
constexpr double kRateSeconds = 1.0;
constexpr double kLongSolveSeconds = 120.0;

// "3 minutes", "5 hours", "2 days": a projected solve time for a message.
std::string DescribeDuration(double seconds)
{
  struct Unit
  {
    double Seconds;
    const char* Name;
  };
  const Unit units[] = { { 86400.0 * 365.0, "years" }, { 86400.0, "days" }, { 3600.0, "hours" },
    { 60.0, "minutes" } };
  for (const Unit& u : units)
  {
    if (seconds >= 2.0 * u.Seconds)
    {
      std::ostringstream text;
      text << static_cast<long long>(std::min(seconds / u.Seconds, 1e15) + 0.5) << " " << u.Name;
      return text.str();
    }
  }
  return std::to_string(static_cast<long long>(seconds + 0.5)) + " seconds";
}

// Adds a note to the filter's progress text (what ParaView's progress bar
// shows) for the rest of a batch, and puts the text back when the batch
// ends, however it ends.
class ProgressLabel
{
public:
  ProgressLabel() = default;
  ProgressLabel(const ProgressLabel&) = delete;
  ProgressLabel& operator=(const ProgressLabel&) = delete;
  ~ProgressLabel()
  {
    if (this->Algorithm)
    {
      this->Algorithm->SetProgressText(this->Had ? this->Before.c_str() : nullptr);
    }
  }
  void Show(vtkAlgorithm* algorithm, const std::string& note)
  {
    if (!this->Algorithm)
    {
      this->Algorithm = algorithm;
      this->Had = algorithm->GetProgressText() != nullptr;
      this->Before = this->Had ? algorithm->GetProgressText() : "";
    }
    std::string name = this->Before;
    if (name.empty())
    {
      // ParaView's label for an algorithm without a text: its class name
      // without "vtk".
      name = algorithm->GetClassName();
      name = name.rfind("vtk", 0) == 0 ? name.substr(3) : name;
    }
    algorithm->SetProgressText((name + ", " + note).c_str());
  }

private:
  vtkAlgorithm* Algorithm = nullptr;
  bool Had = false;
  std::string Before;
};

// Hands a warning, written as VTK's macros take it, to the run's Warn.
#define GRIDFREE_WARN(text)                                                                        \
  do                                                                                               \
  {                                                                                                \
    std::ostringstream warning;                                                                    \
    warning text;                                                                                  \
    warn(warning.str());                                                                           \
  } while (false)

template <int DIM>
bool Estimate(vtkAlgorithm* self, const BuiltProblem& built, const SolveSettings& s,
  const std::vector<std::array<double, 3>>& probePoints, vtkPointData* pd, vtkFieldData* fd,
  const PointEstimateRun& run, PointEstimateSummary& result)
{
  const Problem<DIM>& problem = built.Get<DIM>();
  const Boundary<DIM>& geometry = problem.GetBoundary();
  // Walk on stars: the reflecting part counts for the distance; the closest
  // boundary value is the Dirichlet part's (NaN without one).
  const MixedBoundary<DIM>* mixed = problem.GetMixedBoundary();
  const bool biharmonic = built.Biharmonic;
  const int nc = built.Components;
  auto warn = [&run](const std::string& text)
  {
    if (run.Warn)
    {
      run.Warn(text);
    }
  };
  // The output arrays are named after the boundary array; a probe array of
  // the same name (a Plane's Normals chosen as boundary values, an earlier
  // solve's T) is kept, and the solution takes the name NAME_Solution.
  std::string name = built.Name;
  auto collides = [pd](const std::string& stem)
  {
    for (const char* suffix : { "", "_Variance", "_Gradient", "_Hessian", "_Laplacian",
           "_VarianceReliable", "_VarianceRelativeError" })
    {
      if (pd->GetAbstractArray((stem + suffix).c_str()))
      {
        return true;
      }
    }
    return false;
  };
  while (collides(name))
  {
    name += "_Solution";
  }
  if (name != built.Name)
  {
    GRIDFREE_WARN(<< "The probe has its own array '" << built.Name
                  << "' (or one named after it): the solution is named '" << name
                  << "' instead (its variance '" << name << "_Variance'), and the probe's array is kept.");
  }

  const auto numPoints = static_cast<vtkIdType>(probePoints.size());
  vtkIdType nonFinitePoints = 0;
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    bool finite = true;
    for (int k = 0; k < DIM; ++k)
    {
      finite = finite && std::isfinite(probePoints[i][k]);
    }
    nonFinitePoints += finite ? 0 : 1;
  }
  if (nonFinitePoints > 0)
  {
    GRIDFREE_WARN(<< nonFinitePoints << " of " << numPoints
                  << " probe points have NaN or infinite coordinates: their "
                     "results are NaN.");
  }
  // Walk on stars solves inside the closed boundary only (the reflecting
  // part's normals say which side the domain is on): points outside it are
  // left out, with NaN results, rather than given an exterior problem's
  // answer with the wrong orientation.
  std::vector<std::array<double, 3>> insidePoints;
  std::atomic<vtkIdType> outsidePoints{ 0 };
  if (mixed)
  {
    insidePoints = probePoints;
    tbb::parallel_for(tbb::blocked_range<vtkIdType>(0, numPoints, 256),
      [&](const tbb::blocked_range<vtkIdType>& range) {
        for (vtkIdType i = range.begin(); i < range.end(); ++i)
        {
          auto& p = insidePoints[static_cast<std::size_t>(i)];
          Vec<DIM> x;
          if (ProbeStartPoint<DIM>(p.data(), x) && !mixed->Inside(x))
          {
            p.fill(std::numeric_limits<double>::quiet_NaN());
            outsidePoints.fetch_add(1, std::memory_order_relaxed);
          }
        }
      });
    if (outsidePoints.load() > 0)
    {
      GRIDFREE_WARN(<< outsidePoints.load() << " of " << numPoints
                    << " probe points lie outside the closed boundary: mixed boundary "
                       "conditions (walk on stars) solve the interior problem only, so their "
                       "results are NaN (field data OutsidePoints).");
    }
  }
  const std::vector<std::array<double, 3>>& points = mixed ? insidePoints : probePoints;

  auto mean = MakeArray(name, nc, numPoints);
  auto variance = MakeArray(name + "_Variance", nc, numPoints);
  vtkSmartPointer<vtkDoubleArray> laplacian, laplacianVariance;
  if (biharmonic)
  {
    laplacian = MakeArray(name + "_Laplacian", nc, numPoints);
    laplacianVariance = MakeArray(name + "_Laplacian_Variance", nc, numPoints);
  }
  // Whether each point's error bar can be trusted (ErrorBarReliability.h):
  // 1 or 0 (0 also for points an abort left out), and the variance's own
  // relative standard error, which says how far to trust it.
  auto reliable = vtkSmartPointer<vtkUnsignedCharArray>::New();
  reliable->SetName((name + "_VarianceReliable").c_str());
  reliable->SetNumberOfTuples(numPoints);
  reliable->Fill(0);
  auto varianceError = MakeArray(name + "_VarianceRelativeError", 1, numPoints);
  std::atomic<vtkIdType> unevenWeights{ 0 }, oneWalkSpread{ 0 };
  auto steps = MakeArray("WalkSteps", 1, numPoints);
  auto escaped = MakeArray("EscapedFraction", 1, numPoints);
  auto truncated = MakeArray("TruncatedFraction", 1, numPoints);
  // The distance from each point to the boundary (a lower bound for an
  // implicit boundary): where a walk starts, and how far a streamline may
  // step without crossing the boundary.
  auto distance = MakeArray("BoundaryDistance", 1, numPoints);
  // The boundary value at the closest boundary point: what a walk started
  // here would return if it ended at once. It is the "albedo" a denoiser is
  // guided by (paper Sec. 5.2.4): the solution's sharp features follow its
  // jumps, where the closest point switches between distant boundary parts.
  auto closestValue = MakeArray(name + "_ClosestBoundaryValue", nc, numPoints);
  tbb::parallel_for(tbb::blocked_range<vtkIdType>(0, numPoints, 256),
    [&](const tbb::blocked_range<vtkIdType>& range)
    {
      std::vector<double> g(static_cast<std::size_t>(geometry.Components()));
      for (vtkIdType i = range.begin(); i < range.end(); ++i)
      {
        Vec<DIM> x;
        if (ProbeStartPoint<DIM>(points[static_cast<std::size_t>(i)].data(), x))
        {
          double d = geometry.Distance(x);
          if (mixed && mixed->HasReflecting())
          {
            d = std::min(d, mixed->Reflecting().Distance(x));
          }
          distance->SetValue(i, d);
          if (mixed && !mixed->HasDirichlet())
          {
            std::fill(g.begin(), g.end(), std::numeric_limits<double>::quiet_NaN());
          }
          else
          {
            geometry.Evaluate(x, geometry.ClosestPoint(x), g.data());
          }
          for (int c = 0; c < nc; ++c)
          {
            closestValue->SetTypedComponent(i, c, g[static_cast<std::size_t>(c)]);
          }
        }
      }
    });

  // Derivatives: the derivative estimator runs whenever a derivative or a
  // control variate is asked for (the value's control needs the gradient).
  DerivativeRequest request;
  request.Gradient = s.ComputeGradient;
  request.Hessian = s.ComputeHessian;
  // Control variates need the gradient, which walk on stars does not
  // estimate yet.
  request.ControlVariates = s.ControlVariates && !mixed;
  request.AntitheticPairs = s.AntitheticPairs;
  request.Directional = s.ComputeDirectionalDerivative;
  request.Direction = { s.DerivativeDirection[0], s.DerivativeDirection[1],
    s.DerivativeDirection[2] };
  request.DivergenceCurl = s.ComputeGradient && nc == 3;
  const bool anyDerivative = request.Gradient || request.Hessian || request.Directional;
  DerivativeArrays derivatives;
  if (anyDerivative)
  {
    derivatives.Allocate(name, nc, numPoints, request);
  }

  BatchRequest batch;
  batch.WalksPerPoint = s.WalksPerPoint;
  batch.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(s.Seed));
  batch.Threads = s.NumberOfThreads;
  batch.Derivatives = request;
  const int walks = batch.WalksPerPoint;

  // Target-error mode: the standard error each point walks down to.
  double target = 0.0;
  if (s.TargetStandardError > 0.0)
  {
    target = s.TargetStandardError;
    if (s.TargetErrorIsRelative)
    {
      if (!(built.ValueRange > 0.0))
      {
        vtkErrorWithObjectMacro(self, << "TargetStandardError is relative to the boundary values' "
                                         "range, which is "
                                      << (std::isnan(built.ValueRange)
                                             ? "unknown (values given by expressions)"
                                             : "zero (constant boundary values)")
                                      << ": turn TargetErrorIsRelative off and give the target "
                                         "in the solution's units.");
        result.Completed = false;
        return false;
      }
      target *= built.ValueRange;
    }
    batch.TargetStandardError = target;
  }
  // The walks each point took: in the output with a target (points stop
  // at different counts) and after an abort (points hold what they ran).
  auto walksAtPoint = vtkSmartPointer<vtkIntArray>::New();
  walksAtPoint->SetName("WalkCount");
  walksAtPoint->SetNumberOfTuples(numPoints);
  walksAtPoint->Fill(0);

  // Progressive refinement: the batch continues from the running sums the
  // caller kept (it forgot them if anything but WalksPerPoint changed) and
  // keeps its own.

  // Progress counts walks, so that a few points with very many walks each
  // still report it; once the rate is known, a solve projected to take
  // long is announced (abort stays possible: walks run in chunks that
  // check for it).
  bool announced = false;
  ProgressLabel progressLabel;
  auto reportProgress = [&](const BatchProgress& p)
  {
    if (!announced && run.AnnounceLongSolves && p.WalksRun > 0 && p.Seconds >= kRateSeconds)
    {
      announced = true;
      // In target-error mode the walks a point takes are not known ahead:
      // the share of points finished tells the time instead.
      const double projected = target > 0.0
        ? (p.PointsFraction > 0.0 ? p.Seconds / p.PointsFraction : 0.0)
        : p.Seconds * p.WalksToRun / static_cast<double>(p.WalksRun);
      if (projected >= kLongSolveSeconds)
      {
        GRIDFREE_WARN(<< "This solve will take about " << DescribeDuration(projected)
                      << " at the current rate (" << numPoints << " points, " << walks
                      << " walks per point): lower WalksPerPoint or the "
                         "probe's resolution, or abort it.");
        // Also on the progress bar, which ParaView repaints during the
        // solve whatever its Output Messages window does.
        progressLabel.Show(self, "about " + DescribeDuration(projected) + " in all");
      }
    }
    self->UpdateProgress(run.ProgressBegin + (run.ProgressEnd - run.ProgressBegin) * p.Fraction);
    return !self->GetAbortExecute();
  };

  // Copies one finished point's statistics to the output arrays (called
  // for distinct points at once from worker threads).
  const SampleLayout layout = problem.Layout(batch);
  auto storePoint = [&](std::size_t at, const RunningStatistics& stats,
                      const WalkCounters& counters, DerivativeStatus status)
  {
    const auto i = static_cast<vtkIdType>(at);
    for (int c = 0; c < nc; ++c)
    {
      mean->SetValue(i * nc + c, stats.GetMean(layout.Value + c));
      variance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Value + c));
      if (biharmonic)
      {
        laplacian->SetValue(i * nc + c, stats.GetMean(layout.Laplacian + c));
        laplacianVariance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Laplacian + c));
      }
    }
    const ErrorBarCheck check = problem.ErrorBar(stats, counters, layout);
    reliable->SetValue(i, check.Reliable ? 1 : 0);
    varianceError->SetValue(i, check.VarianceRelativeError);
    if (check.WeightVariation > ErrorBarRule().MaxWeightVariation)
    {
      unevenWeights.fetch_add(1, std::memory_order_relaxed);
    }
    else if (!check.Reliable)
    {
      oneWalkSpread.fetch_add(1, std::memory_order_relaxed);
    }
    steps->SetValue(i, counters.MeanSteps());
    walksAtPoint->SetValue(i, static_cast<int>(std::min<std::uint64_t>(counters.Walks, VTK_INT_MAX)));
    escaped->SetValue(i, counters.EscapedFraction());
    truncated->SetValue(i, counters.TruncatedFraction());
    if (anyDerivative)
    {
      derivatives.Store<DIM>(at, stats, layout, nc, static_cast<int>(status));
    }
  };

  const BatchSummary summary =
    problem.Estimate(points, batch, storePoint, reportProgress, run.Kept);
  const bool completed = summary.Completed;
  const WalkCounters& totals = summary.Totals;
  const std::array<std::uint64_t, 3>& statusCounts = summary.StatusCounts;
  const bool unboundedSource = summary.UnboundedSource;
  const int startWalks = summary.ResumedWalksPerPoint;
  result.ResumedWalksPerPoint = startWalks;
  const double seconds = summary.Seconds;

  // Walks run now; the output stands for totals.Walks (kept ones included).
  result.WalksRun = summary.WalksRun;
  result.Seconds = seconds;
  result.Completed = completed;
  result.PointsFinished = static_cast<std::int64_t>(summary.PointsFinished);
  result.PointsWithoutWalks = static_cast<std::int64_t>(summary.PointsWithoutWalks);

  pd->AddArray(mean);
  pd->AddArray(variance);
  if (biharmonic)
  {
    pd->AddArray(laplacian);
    pd->AddArray(laplacianVariance);
  }
  pd->AddArray(reliable);
  pd->AddArray(varianceError);
  pd->AddArray(steps);
  if (target > 0.0 || !completed)
  {
    pd->AddArray(walksAtPoint);
  }
  pd->AddArray(escaped);
  pd->AddArray(truncated);
  pd->AddArray(distance);
  pd->AddArray(closestValue);
  pd->SetActiveScalars(mean->GetName());
  if (anyDerivative)
  {
    derivatives.ZeroWhereMissing();
    derivatives.AddTo(pd, nc);
  }

  const double walkCount = static_cast<double>(totals.Walks);
  // The rate of the walks run now: resumed walks cost nothing.
  const double walksRun = static_cast<double>(summary.WalksRun);
  const double walksPerSecond = seconds > 0.0 ? walksRun / seconds : 0.0;
  const double meanSteps = walkCount > 0.0 ? static_cast<double>(totals.Steps) / walkCount : 0.0;
  const double escapedFraction =
    walkCount > 0.0 ? static_cast<double>(totals.Escaped) / walkCount : 0.0;
  if (fd)
  {
    AddFieldValue(fd, "TotalWalks", static_cast<double>(totals.Walks));
    AddFieldValue(fd, "TotalSteps", static_cast<double>(totals.Steps));
    AddFieldValue(fd, "EscapedWalks", static_cast<double>(totals.Escaped));
    AddFieldValue(fd, "TruncatedWalks", static_cast<double>(totals.Truncated));
    AddFieldValue(fd, "SolveSeconds", seconds);
    // Progressive refinement: walks per point taken from the kept sums.
    AddFieldValue(fd, "ResumedWalksPerPoint", static_cast<double>(startWalks));
    AddFieldValue(fd, "WalksRun", walksRun);
    if (target > 0.0)
    {
      AddFieldValue(fd, "TargetStandardError", target);
    }
    // The run's summary, ready to read in a spreadsheet view or a script.
    AddFieldValue(fd, "ProbePoints", static_cast<double>(numPoints));
    AddFieldValue(fd, "WalksPerSecond", walksPerSecond);
    AddFieldValue(fd, "MeanStepsPerWalk", meanSteps);
    AddFieldValue(fd, "EscapedWalkFraction", escapedFraction);
    AddFieldValue(fd, "UnreliableErrorBars", static_cast<double>(summary.UnreliableErrorBars));
    if (mixed)
    {
      AddFieldValue(fd, "BackFaceHits", static_cast<double>(summary.BackFaceHits));
      AddFieldValue(fd, "OutsidePoints", static_cast<double>(outsidePoints.load()));
    }
  }
  result.UnreliableErrorBars = static_cast<std::int64_t>(summary.UnreliableErrorBars);
  // Debug level: shown in ParaView's Output Messages when the filter's
  // Debug property (advanced) is on, and by vtkObject::DebugOn elsewhere.
  // Not vtkDebugWithObjectMacro: release builds (NDEBUG) compile it out.
  if (self->GetDebug() && vtkObject::GetGlobalWarningDisplay())
  {
    std::ostringstream msg;
    msg << self->GetObjectDescription() << ": summary: " << numPoints << " probe points, "
        << totals.Walks << " walks (" << summary.WalksRun << " run now), " << seconds << " s, "
        << walksPerSecond << " walks/s, "
        << meanSteps << " steps per walk, escaped fraction " << escapedFraction;
    vtkOutputWindowDisplayDebugText(
      "GridFreePointEstimates.cxx", __LINE__, msg.str().c_str(), self);
  }

  if (summary.BackFaceHits > 0 && startWalks == 0)
  {
    GRIDFREE_WARN(<< summary.BackFaceHits
                  << " walks met a Neumann or Robin cell from outside the domain (field data "
                     "BackFaceHits): those cells' normals must point out of the domain, and the "
                     "boundary must be closed around the probe. Check their orientation (e.g. "
                     "ParaView's Generate Surface Normals with Consistency and Auto Orient) and "
                     "leaks; results near them are wrong.");
  }
  if (!completed)
  {
    std::ostringstream rest;
    const vtkIdType unfinished = numPoints - static_cast<vtkIdType>(summary.PointsFinished);
    const vtkIdType withWalks = unfinished - static_cast<vtkIdType>(summary.PointsWithoutWalks);
    if (withWalks > 0)
    {
      rest << " " << withWalks << " show the estimate of the walks they hold"
           << (startWalks > 0 ? " (this solve's so far, or the earlier solve's)" : "")
           << ", fewer than asked (WalkCount).";
    }
    if (summary.PointsWithoutWalks > 0)
    {
      rest << " " << summary.PointsWithoutWalks
           << " have no walks yet: their values are NaN (WalkCount 0)"
           << (anyDerivative ? " and their derivatives 0 (DerivativeStatus 2)" : "") << ".";
    }
    GRIDFREE_WARN(<< "Solve aborted after " << DescribeDuration(seconds) << ": "
                  << summary.PointsFinished << " of " << numPoints << " probe points have all "
                  << (target > 0.0 ? "the walks they need" : std::to_string(walks) + " walks")
                  << "." << rest.str()
                  << " Apply again (Resume() and Update() in a script) to continue from the "
                     "walks already run.");
    return false;
  }
  if (target > 0.0)
  {
    // Points that took every walk allowed without reaching the target.
    vtkIdType unreached = 0;
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      bool above = false;
      for (int c = 0; c < nc; ++c)
      {
        above = above || !(variance->GetValue(i * nc + c) <= target * target);
      }
      unreached += (above && walksAtPoint->GetValue(i) >= walks) ? 1 : 0;
    }
    result.PointsShortOfTarget = static_cast<std::int64_t>(unreached);
    if (target > 0.0 && fd)
    {
      AddFieldValue(fd, "PointsShortOfTarget", static_cast<double>(unreached));
    }
    // Said once, by the solve that starts afresh: a solve that continues
    // from kept sums (Refine, Refine Until Target's rounds) is refining on
    // purpose, and PointsShortOfTarget has the count.
    if (unreached > 0 && startWalks == 0 && run.ReportShortOfTarget)
    {
      GRIDFREE_WARN(<< unreached << " of " << numPoints << " probe points took all " << walks
                    << " walks (Walks Per Point, the most a point may take) without reaching "
                       "the target standard error "
                    << target
                    << ": raise Walks Per Point or the target, or refine (Refine Until Target "
                       "in the GUI).");
    }
  }
  // Error bars that cannot be trusted: said by the solve that starts
  // afresh (a refinement continues on purpose; the field and the array
  // keep the count).
  if (summary.UnreliableErrorBars > 0 && startWalks == 0 && run.ReportUnreliableErrorBars)
  {
    std::ostringstream why;
    if (unevenWeights.load() > 0)
    {
      why << " " << unevenWeights.load()
          << " of them because their walks' screening weights are very uneven (the screening "
             "length 1/sqrt(ScreeningCoefficient) is short against the distance to the "
             "boundary): their value rests on rare walks, and more walks do not remove the "
             "doubt; compare solves with different seeds and walk counts before using them.";
    }
    if (oneWalkSpread.load() > 0)
    {
      why << " " << oneWalkSpread.load()
          << " of them because all their walks, or all but one, gave the same value although "
             "they could have given others: raise Walks Per Point, or set a target standard "
             "error, which walks on at such points.";
    }
    GRIDFREE_WARN(<< summary.UnreliableErrorBars << " of " << numPoints << " probe points have "
                  << "error bars that cannot be trusted (" << name
                  << "_VarianceReliable = 0): their " << name
                  << "_Variance may be far too small." << why.str());
  }
  // NaN results of finite probe points: walks whose coordinates overflowed
  // (points far beyond the boundary's scale) end with no boundary value.
  vtkIdType nanResults = -nonFinitePoints - outsidePoints.load();
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    nanResults += std::isnan(mean->GetValue(i * nc)) ? 1 : 0;
  }
  if (nanResults > 0)
  {
    GRIDFREE_WARN(<< nanResults << " of " << numPoints
                  << " probe points got NaN results: their walks overflowed "
                     "(coordinates far beyond the boundary's size?).");
  }
  if (totals.Escaped > 0 && biharmonic)
  {
    GRIDFREE_WARN(<< totals.Escaped << " of " << totals.Walks
                  << " biharmonic walks left the region enclosed by the "
                     "boundary and were counted as 0 (see EscapedFraction): "
                     "the biharmonic solver is for bounded domains.");
  }
  if (unboundedSource && (totals.Escaped > 0 || totals.Returns > 0))
  {
    GRIDFREE_WARN(<< "Walks reached the exterior region, where the "
                     "SourceExpression is taken as zero beyond a sphere "
                     "around the boundary and the Source input.");
  }
  if (anyDerivative && (statusCounts[1] > 0 || statusCounts[2] > 0))
  {
    vtkDebugWithObjectMacro(self, << statusCounts[1] << " probe points lie closer than Epsilon "
                                  << "to the boundary and got one-sided derivatives; "
                                  << statusCounts[2] << " got none (see DerivativeStatus).");
  }
  if (totals.Truncated > 0)
  {
    GRIDFREE_WARN(<< totals.Truncated << " of " << totals.Walks << " walks reached MaxSteps = "
                  << s.MaxSteps << " and were stopped (see TruncatedFraction).");
  }
  return true;
}
} // namespace

std::vector<std::array<double, 3>> PointsOf(vtkDataSet* data)
{
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(data->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    data->GetPoint(i, points[static_cast<std::size_t>(i)].data());
  }
  return points;
}

bool EstimateAtPoints(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, const std::vector<std::array<double, 3>>& points,
  vtkPointData* arrays, vtkFieldData* fieldData, const PointEstimateRun& run,
  PointEstimateSummary& summary)
{
  summary = PointEstimateSummary();
  return problem.Dimension == 2
    ? Estimate<2>(reporter, problem, settings, points, arrays, fieldData, run, summary)
    : Estimate<3>(reporter, problem, settings, points, arrays, fieldData, run, summary);
}
} // namespace gridfree
