// What a batch of estimates asks for and what it gives back: the request
// (walks, seed, threads, derivatives, target), the progress reports, the
// per-point sink, the summary, and every point's numbers collected
// (Problem::EstimateAll). Problem.h answers batches; BatchScheduler.h runs
// them on the threads.
#ifndef GRIDFREE_PROBLEM_BATCH_H
#define GRIDFREE_PROBLEM_BATCH_H

#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/statistics/ErrorBarReliability.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace gridfree
{
// What one batch asks for.
struct BatchRequest
{
  int WalksPerPoint = 128;
  std::uint64_t Seed = 0;
  // Threads to run on; 0 = all.
  int Threads = 0;
  // Derivatives (gradient, Hessian, directional derivative, divergence and
  // curl) and control variates. Any of them runs the derivative estimator
  // (DerivativeWalkOnSpheres.h), which also gives the value; none runs the
  // plain one (WalkOnSpheres.h). Control variates are off unless asked for.
  DerivativeRequest Derivatives = NoDerivatives();
  // Target-error mode (when positive): a point stops walking once the
  // standard error of its value (the largest over the solution's components)
  // is at most this, checked after PointWalks::kTargetFirstWalks walks
  // and then every PointWalks::kTargetCheckWalks (PointWalks.h);
  // WalksPerPoint is then the most any point takes. The decision depends
  // only on the point's own walks, so the result is the same for any
  // thread count. A batch with a larger WalksPerPoint resumes
  // from kept sums in this mode too: points that stopped at the target keep
  // their numbers, the others continue, as one batch with that maximum would.
  // A point whose error bar is not reliable (ErrorBarReliability.h) does not
  // stop: its small standard error may be an artefact of heavy tails.
  double TargetStandardError = 0.0;
  // Fixed-count mode: a point whose error bar is not reliable after
  // WalksPerPoint walks walks on, checked at 2, 4, ... times WalksPerPoint
  // (PointWalks::WalkOnUntilReliable), until it is reliable or holds this
  // many times WalksPerPoint (1: no point walks on). A spread made by one
  // walk is settled by more walks: they bring the rare walks that were
  // due, and the error bar with them, or the point stays flagged. Uneven
  // screening weights do not even out with walks (ErrorBarReliability.h):
  // a point flagged for them walks on only if the walk values' bound would
  // clear it at the most walks. The decision depends only on the point's
  // own walks, so the numbers do not depend on the thread count. A later
  // batch from kept sums continues each point from the walks it holds, and
  // gives the numbers of one batch when its count is the earlier one's
  // times a power of 2 (otherwise a point that walked on past its count
  // keeps its walks). Not used in target-error mode, where an unreliable
  // point already walks on.
  int WalkOnWhereUnreliable = 1;
  // A problem with a polynomial control variate (Problem::SetPolynomialShift)
  // answers u = P + w; false asks for w itself, at every point (the
  // caches, which hold w and add P to their own answers).
  bool AddPolynomialShift = true;

  bool DerivativeWalks() const
  {
    return this->Derivatives.Gradient || this->Derivatives.Hessian ||
      this->Derivatives.Directional || this->Derivatives.ControlVariates;
  }

  static DerivativeRequest NoDerivatives()
  {
    DerivativeRequest none;
    none.ControlVariates = false;
    return none;
  }
};

// Where a batch stands, for a progress report.
struct BatchProgress
{
  // Of the batch's work done: walks run over walks to run, or points
  // finished over points, whichever is further.
  double Fraction = 0.0;
  std::uint64_t WalksRun = 0;
  double WalksToRun = 0.0;
  double Seconds = 0.0;
  // Points finished over points (target-error mode: the walks a point takes
  // are not known ahead, so this is the measure of progress).
  double PointsFraction = 0.0;
};

// Called on the calling thread about ten times a second; returning false
// aborts the batch (walks stop within one chunk of 1024 walks).
using BatchProgressCallback = std::function<bool(const BatchProgress&)>;

// Receives a finished point: its running statistics (Layout().Size numbers
// per walk, at the slots of the batch's layout), its counters and, for the
// derivative estimator, its status. Called for distinct points at once on
// worker threads: writing to per-point storage needs no lock.
using PointSink = std::function<void(
  std::size_t point, const RunningStatistics& stats, const WalkCounters& counters,
  DerivativeStatus status)>;

// What a batch did, over the points it finished.
struct BatchSummary
{
  bool Completed = false; // false: aborted, some points never reached the sink
  SampleLayout Layout;    // the slots of each point's statistics
  int ResumedWalksPerPoint = 0; // walks per point taken from kept sums
  std::uint64_t WalksRun = 0;   // walks run by this batch (resumed ones excluded)
  WalkCounters Totals;          // over finished points, resumed walks included
  std::array<std::uint64_t, 3> StatusCounts = { 0, 0, 0 }; // per DerivativeStatus
  bool UnboundedSource = false; // a volume source with unbounded support met the exterior
  // Finished points whose error bar is not reliable (ErrorBarReliability.h).
  std::uint64_t UnreliableErrorBars = 0;
  // Points that walked on past WalksPerPoint for a reliable error bar
  // (BatchRequest::WalkOnWhereUnreliable), and the walks they added.
  std::uint64_t PointsWalkedOn = 0;
  std::uint64_t WalksOnForReliability = 0;
  // Walk on stars: rays that met the Neumann or Robin part from outside
  // (WalkOnStarsEstimator::BackFaceHits), the sign of a wrongly oriented or
  // leaking reflecting surface; 0 otherwise.
  std::uint64_t BackFaceHits = 0;
  // Points that ran all their walks (every point of a complete batch); an
  // aborted batch with kept sums hands the others to the sink with the
  // walks they hold, but for PointsWithoutWalks, which hold none.
  std::uint64_t PointsFinished = 0;
  std::uint64_t PointsWithoutWalks = 0;
  // Points outside the closed boundary of a problem with a polynomial
  // control variate (Problem::SetPolynomialShift): NaN.
  std::uint64_t PointsOutsideShift = 0;
  double Seconds = 0.0;
};

// Every point's means and variances of the mean, collected (EstimateAll).
struct BatchEstimates
{
  BatchSummary Summary;
  std::size_t Points = 0;
  std::vector<double> Means;     // Points × Layout.Size
  std::vector<double> Variances; // Points × Layout.Size (variance of the mean)
  std::vector<WalkCounters> Counters;
  std::vector<DerivativeStatus> Status;
  std::vector<unsigned char> Finished; // 0 for points an abort left out
  std::vector<ErrorBarCheck> ErrorBars;

  double Mean(std::size_t point, int slot) const
  {
    return this->Means[point * static_cast<std::size_t>(this->Summary.Layout.Size) + slot];
  }
  double Variance(std::size_t point, int slot) const
  {
    return this->Variances[point * static_cast<std::size_t>(this->Summary.Layout.Size) + slot];
  }
  // Component c of the solution, and its variance.
  double Value(std::size_t point, int c = 0) const
  {
    return this->Mean(point, this->Summary.Layout.Value + c);
  }
  double ValueVariance(std::size_t point, int c = 0) const
  {
    return this->Variance(point, this->Summary.Layout.Value + c);
  }
};

} // namespace gridfree

#endif
