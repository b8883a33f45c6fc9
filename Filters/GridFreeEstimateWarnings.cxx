#include "GridFreeEstimateWarnings.h"

#include "vtkAlgorithm.h"
#include "vtkOutputWindow.h"
#include "vtkSetGet.h"

#include <algorithm>
#include <sstream>
#include <string>

namespace gridfree
{
// Hands a warning, written as VTK's macros take it, to `warn`.
#define GRIDFREE_WARN(text)                                                                        \
  do                                                                                               \
  {                                                                                                \
    std::ostringstream warning;                                                                    \
    warning text;                                                                                  \
    warn(warning.str());                                                                           \
  } while (false)

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

std::string LongSolveWarning(double projected, std::int64_t points, int walksPerPoint)
{
  std::ostringstream text;
  text << "This solve will take about " << DescribeDuration(projected)
       << " at the current rate (" << points << " points, " << walksPerPoint
       << " walks per point): lower WalksPerPoint or the "
          "probe's resolution, or abort it.";
  return text.str();
}

namespace
{
void WarnAboutAbort(const BatchFindings& f, const std::function<void(const std::string&)>& warn)
{
  std::ostringstream rest;
  const std::int64_t unfinished = f.Points - static_cast<std::int64_t>(f.PointsFinished);
  const std::int64_t withWalks = unfinished - static_cast<std::int64_t>(f.PointsWithoutWalks);
  if (withWalks > 0)
  {
    rest << " " << withWalks << " show the estimate of the walks they hold"
         << (f.ResumedWalksPerPoint > 0 ? " (this solve's so far, or the earlier solve's)" : "")
         << ", fewer than asked (WalkCount).";
  }
  if (f.PointsWithoutWalks > 0)
  {
    rest << " " << f.PointsWithoutWalks
         << " have no walks yet: their values are NaN (WalkCount 0)"
         << (f.AnyDerivative ? " and their derivatives 0 (DerivativeStatus 2)" : "") << ".";
  }
  GRIDFREE_WARN(<< "Solve aborted after " << DescribeDuration(f.Seconds) << ": "
                << f.PointsFinished << " of " << f.Points << " probe points have all "
                << (f.Target > 0.0 ? "the walks they need"
                                   : std::to_string(f.WalksPerPoint) + " walks")
                << "." << rest.str()
                << " Apply again (Resume() and Update() in a script) to continue from the "
                   "walks already run.");
}

void WarnAboutUnreliableErrorBars(
  const BatchFindings& f, const std::function<void(const std::string&)>& warn)
{
  std::ostringstream why;
  if (f.UnevenWeights > 0)
  {
    why << " " << f.UnevenWeights
        << " of them because their walks' screening weights are very uneven (the screening "
           "length 1/sqrt(ScreeningCoefficient) is short against the distance to the "
           "boundary): their value rests on rare walks, and more walks do not remove the "
           "doubt. ScreenedSteps = Guided lands the steps where the answer comes from; "
           "or compare solves with different seeds and walk counts before using them.";
  }
  if (f.OneWalkSpread > 0)
  {
    const bool walkedOn = f.WalkOnWhereUnreliable > 1 && f.Target <= 0.0;
    why << " " << f.OneWalkSpread
        << " of them because all their walks, or all but one, gave the same value although "
           "they could have given others, or their spread comes from two or three walks "
           "(data that jump, read with few walks)"
        << (walkedOn ? " (even after walking on up to " +
                std::to_string(f.WalkOnWhereUnreliable) +
                " times Walks Per Point: Walk On Where Unreliable)"
                     : std::string())
        << ": raise Walks Per Point, or set a target standard error, which walks on at such "
           "points.";
  }
  GRIDFREE_WARN(<< f.UnreliableErrorBars << " of " << f.Points << " probe points have "
                << "error bars that cannot be trusted (" << f.Name
                << "_VarianceReliable = 0): their " << f.Name
                << "_Variance may be far too small." << why.str());
}
} // namespace

void WarnAboutBatch(vtkAlgorithm* self, const BatchFindings& f, const BatchWarningChoice& choice,
  const std::function<void(const std::string&)>& warn)
{
  // Said by the solve that starts afresh: a solve that continues from kept
  // sums (Refine, Refine Until Target's rounds) refines on purpose, and the
  // field data keep the counts.
  const bool fresh = f.ResumedWalksPerPoint == 0;
  if (f.BackFaceHits > 0 && fresh)
  {
    GRIDFREE_WARN(<< f.BackFaceHits
                  << " walks met a Neumann or Robin cell from outside the domain (field data "
                     "BackFaceHits): those cells' normals must point out of the domain, and the "
                     "boundary must be closed around the probe. Check their orientation (e.g. "
                     "ParaView's Generate Surface Normals with Consistency and Auto Orient) and "
                     "leaks; results near them are wrong.");
  }
  if (f.PointsOutsideShift > 0 && fresh)
  {
    GRIDFREE_WARN(<< f.PointsOutsideShift << " of " << f.Points
                  << " probe points lie outside the closed boundary and are NaN: the polynomial "
                     "control variate answers the interior problem only (set "
                     "PolynomialControlVariate to 0 to solve outside as well).");
  }
  if (!f.Completed)
  {
    WarnAboutAbort(f, warn);
    return;
  }
  // Points that took every walk allowed without reaching the target.
  if (f.Target > 0.0 && f.PointsShortOfTarget > 0 && fresh && choice.ShortOfTarget)
  {
    GRIDFREE_WARN(<< f.PointsShortOfTarget << " of " << f.Points << " probe points took all "
                  << f.WalksPerPoint
                  << " walks (Walks Per Point, the most a point may take) without reaching "
                     "the target standard error "
                  << f.Target
                  << ": raise Walks Per Point or the target, or refine (Refine Until Target "
                     "in the GUI).");
  }
  if (f.UnreliableErrorBars > 0 && fresh && choice.UnreliableErrorBars)
  {
    WarnAboutUnreliableErrorBars(f, warn);
  }
  if (f.NanResults > 0)
  {
    GRIDFREE_WARN(<< f.NanResults << " of " << f.Points
                  << " probe points got NaN results: their walks overflowed "
                     "(coordinates far beyond the boundary's size?).");
  }
  if (f.Escaped > 0 && f.Biharmonic)
  {
    GRIDFREE_WARN(<< f.Escaped << " of " << f.Walks
                  << " biharmonic walks left the region enclosed by the "
                     "boundary and were counted as 0 (see EscapedFraction): "
                     "the biharmonic solver is for bounded domains.");
  }
  if (f.UnboundedSource && (f.Escaped > 0 || f.Returns > 0))
  {
    GRIDFREE_WARN(<< "Walks reached the exterior region, where the "
                     "SourceExpression is taken as zero beyond a sphere "
                     "around the boundary and the Source input.");
  }
  if (f.AnyDerivative && (f.StatusCounts[1] > 0 || f.StatusCounts[2] > 0))
  {
    vtkDebugWithObjectMacro(self, << f.StatusCounts[1] << " probe points lie closer than Epsilon "
                                  << "to the boundary and got one-sided derivatives; "
                                  << f.StatusCounts[2] << " got none (see DerivativeStatus).");
  }
  if (f.Truncated > 0)
  {
    GRIDFREE_WARN(<< f.Truncated << " of " << f.Walks << " walks reached MaxSteps = "
                  << f.MaxSteps << " and were stopped (see TruncatedFraction).");
  }
}

void DebugSummary(vtkAlgorithm* self, const BatchFindings& f)
{
  // Debug level: shown in ParaView's Output Messages when the filter's
  // Debug property (advanced) is on, and by vtkObject::DebugOn elsewhere.
  // Not vtkDebugWithObjectMacro: release builds (NDEBUG) compile it out.
  if (!self->GetDebug() || !vtkObject::GetGlobalWarningDisplay())
  {
    return;
  }
  const double walks = static_cast<double>(f.Walks);
  const double walksPerSecond = f.Seconds > 0.0 ? static_cast<double>(f.WalksRun) / f.Seconds : 0.0;
  std::ostringstream msg;
  msg << self->GetObjectDescription() << ": summary: " << f.Points << " probe points, "
      << f.Walks << " walks (" << f.WalksRun << " run now), " << f.Seconds << " s, "
      << walksPerSecond << " walks/s, "
      << (walks > 0.0 ? static_cast<double>(f.Steps) / walks : 0.0)
      << " steps per walk, escaped fraction "
      << (walks > 0.0 ? static_cast<double>(f.Escaped) / walks : 0.0);
  vtkOutputWindowDisplayDebugText(
    "GridFreeEstimateWarnings.cxx", __LINE__, msg.str().c_str(), self);
}
} // namespace gridfree
