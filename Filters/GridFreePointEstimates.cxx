#include "GridFreePointEstimates.h"

#include "GridFreeArrays.h"
#include "GridFreeCacheAnswers.h"
#include "GridFreeEstimateArrays.h"
#include "GridFreeEstimateWarnings.h"
#include "GridFreePointNumbers.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"

#include <gridfree/problem/Problem.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "vtkAlgorithm.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace gridfree
{
namespace
{
// A batch projected (after kRateSeconds of measuring) to take longer than
// kLongSolveSeconds is announced with a warning.
constexpr double kRateSeconds = 1.0;
constexpr double kLongSolveSeconds = 120.0;

using Warn = std::function<void(const std::string&)>;

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

// The name of the solution arrays: the boundary array's, unless the probe
// has an array of that name (a Plane's Normals chosen as boundary values,
// an earlier solve's T), which is kept while the solution takes the name
// NAME_Solution. Estimates that go to no output (null `pd`) keep the name.
std::string SolutionName(const std::string& wanted, vtkPointData* pd, const Warn& warn)
{
  if (!pd)
  {
    return wanted;
  }
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
  std::string name = wanted;
  while (collides(name))
  {
    name += "_Solution";
  }
  if (name != wanted)
  {
    std::ostringstream text;
    text << "The probe has its own array '" << wanted
         << "' (or one named after it): the solution is named '" << name
         << "' instead (its variance '" << name
         << "_Variance'), and the probe's array is kept.";
    warn(text.str());
  }
  return name;
}

// The points the walks start from, and those that get NaN results without
// walking: points with NaN or infinite coordinates, and, with mixed
// conditions where the exterior problem is not solved (the Poisson
// equation, sources: Problem::AnswersOutside), points outside
// the closed boundary, rather than an answer of the interior problem walked
// from the wrong side.
template <int DIM>
struct StartPoints
{
  std::vector<std::array<double, 3>> Inside; // the probe's; outside ones NaN if not answered
  std::int64_t NonFinite = 0;
  std::int64_t Outside = 0;

  const std::vector<std::array<double, 3>>& Of(
    const std::vector<std::array<double, 3>>& probePoints, bool mixed) const
  {
    return mixed ? this->Inside : probePoints;
  }

  void Find(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& probePoints,
    const Warn& warn)
  {
    const auto n = static_cast<std::int64_t>(probePoints.size());
    for (const std::array<double, 3>& p : probePoints)
    {
      bool finite = true;
      for (int k = 0; k < DIM; ++k)
      {
        finite = finite && std::isfinite(p[static_cast<std::size_t>(k)]);
      }
      this->NonFinite += finite ? 0 : 1;
    }
    if (this->NonFinite > 0)
    {
      std::ostringstream text;
      text << this->NonFinite << " of " << n
           << " probe points have NaN or infinite coordinates: their results are NaN.";
      warn(text.str());
    }
    const MixedBoundary<DIM>* mixed = problem.GetMixedBoundary();
    if (!mixed)
    {
      return;
    }
    this->Inside = probePoints;
    if (problem.AnswersOutside())
    {
      return;
    }
    std::atomic<std::int64_t> outside{ 0 };
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, n, 256),
      [&](const tbb::blocked_range<std::int64_t>& range) {
        for (std::int64_t i = range.begin(); i < range.end(); ++i)
        {
          auto& p = this->Inside[static_cast<std::size_t>(i)];
          Vec<DIM> x;
          if (ProbeStartPoint<DIM>(p.data(), x) && !mixed->Inside(x))
          {
            p.fill(std::numeric_limits<double>::quiet_NaN());
            outside.fetch_add(1, std::memory_order_relaxed);
          }
        }
      });
    this->Outside = outside.load();
    if (this->Outside > 0)
    {
      std::ostringstream text;
      text << this->Outside << " of " << n
           << " probe points lie outside the closed boundary: their results are NaN (field "
              "data OutsidePoints). With mixed boundary conditions (walk on stars) the exterior "
              "problem is solved for the Laplace equation, or the screened Poisson equation "
              "without a source.";
      warn(text.str());
    }
  }
};

// The distance to the boundary and the closest boundary value at each
// point. Walk on stars: the reflecting part counts for the distance; the
// closest boundary value is the Dirichlet part's (NaN without one).
template <int DIM, class Storage>
void FillBoundaryArrays(
  const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& points, Storage& arrays)
{
  const Boundary<DIM>& geometry = problem.GetBoundary();
  const MixedBoundary<DIM>* mixed = problem.GetMixedBoundary();
  const int nc = arrays.Components();
  tbb::parallel_for(tbb::blocked_range<vtkIdType>(0, static_cast<vtkIdType>(points.size()), 256),
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
          arrays.SetDistance(i, d);
          if (!Storage::kClosestValues)
          {
            continue;
          }
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
            arrays.SetClosestValue(i, c, g[static_cast<std::size_t>(c)]);
          }
        }
      }
    });
}

// The derivatives asked for: the derivative estimator runs whenever a
// derivative or a control variate is asked for (the value's control needs
// the gradient; with mixed conditions too, StarDerivativeWalks.h).
DerivativeRequest DerivativesOf(const SolveSettings& s, int nc, bool cache)
{
  DerivativeRequest request;
  request.Gradient = s.ComputeGradient;
  request.Hessian = s.ComputeHessian;
  request.ControlVariates = s.ControlVariates;
  request.AntitheticPairs = s.AntitheticPairs;
  request.Directional = s.ComputeDirectionalDerivative;
  request.Direction = { s.DerivativeDirection[0], s.DerivativeDirection[1],
    s.DerivativeDirection[2] };
  // (The boundary cache gives no divergence or curl, whose variances need
  // the gradient's covariances; the sphere cache's come from its samples.)
  request.DivergenceCurl =
    s.ComputeGradient && nc == 3 && (!cache || s.Estimator == Estimator::SphereCache);
  return request;
}

// Points outside the closed boundary, which the caches do not answer.
void WarnOfPointsOutside(std::int64_t outside, std::int64_t points, const Warn& warn)
{
  if (outside > 0)
  {
    std::ostringstream text;
    text << outside << " of " << points
         << " probe points lie outside the closed boundary: the cache estimators solve the "
            "interior problem only, so their results are NaN (field data OutsidePoints). "
            "Choose the Pointwise Walks estimator for the exterior.";
    warn(text.str());
  }
}

// A cache's part of a batch, in field data: how many points it answered,
// its size, and what this batch spent on it (CacheWalksRun 0: the cache
// was reused as it was). `outsideBefore`: the points a mixed problem's
// inside test left out before the cache saw them (StartPoints).
void AddCacheFields(vtkFieldData* fd, const CacheAnswers& cached, std::int64_t outsideBefore)
{
  AddFieldValue(fd, "PointsFromCache", static_cast<double>(cached.Answered));
  AddFieldValue(fd, "PointsWalkedInShell", static_cast<double>(cached.Walked.size()));
  AddFieldValue(fd, "OutsidePoints", static_cast<double>(cached.Outside + outsideBefore));
  for (const auto& figure : cached.Figures)
  {
    AddFieldValue(fd, figure.first.c_str(), figure.second);
  }
  AddFieldValue(fd, "CacheWalksRun", static_cast<double>(cached.WalksRun));
  AddFieldValue(fd, "CacheSeconds", cached.Seconds);
}

// The batch the settings ask for: walks, seed, threads, derivatives and, in
// target-error mode, the standard error each point walks down to (a
// relative target scaled by the boundary values' range). False, with an
// error on `self`, when a relative target has no range to refer to.
bool MakeBatchRequest(vtkAlgorithm* self, const SolveSettings& s, const BuiltProblem& built,
  const DerivativeRequest& derivatives, BatchRequest& batch)
{
  batch.WalksPerPoint = s.WalksPerPoint;
  batch.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(s.Seed));
  batch.Threads = s.NumberOfThreads;
  batch.Derivatives = derivatives;
  batch.WalkOnWhereUnreliable = s.WalkOnWhereUnreliable;
  if (!(s.TargetStandardError > 0.0))
  {
    return true;
  }
  double target = s.TargetStandardError;
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
      return false;
    }
    target *= built.ValueRange;
  }
  batch.TargetStandardError = target;
  return true;
}

// Progress counts walks, so that a few points with very many walks each
// still report it; once the rate is known, a solve projected to take long
// is announced (abort stays possible: walks run in chunks that check for
// it). Returns false to abort.
class ProgressReporter
{
public:
  ProgressReporter(vtkAlgorithm* self, const PointEstimateRun& run, const Warn& warn,
    std::int64_t points, int walksPerPoint, double target)
    : Self(self)
    , Run(run)
    , WarnOf(warn)
    , Points(points)
    , WalksPerPoint(walksPerPoint)
    , Target(target)
  {
  }

  bool operator()(const BatchProgress& p)
  {
    if (!this->Announced && this->Run.AnnounceLongSolves && p.WalksRun > 0 &&
      p.Seconds >= kRateSeconds)
    {
      this->Announced = true;
      // In target-error mode the walks a point takes are not known ahead:
      // the share of points finished tells the time instead.
      const double projected = this->Target > 0.0
        ? (p.PointsFraction > 0.0 ? p.Seconds / p.PointsFraction : 0.0)
        : p.Seconds * p.WalksToRun / static_cast<double>(p.WalksRun);
      if (projected >= kLongSolveSeconds)
      {
        this->WarnOf(LongSolveWarning(projected, this->Points, this->WalksPerPoint));
        // Also on the progress bar, which ParaView repaints during the
        // solve whatever its Output Messages window does.
        this->Label.Show(this->Self, "about " + DescribeDuration(projected) + " in all");
      }
    }
    this->Self->UpdateProgress(
      this->Run.ProgressBegin + (this->Run.ProgressEnd - this->Run.ProgressBegin) * p.Fraction);
    return !this->Self->GetAbortExecute();
  }

private:
  vtkAlgorithm* Self;
  const PointEstimateRun& Run;
  const Warn& WarnOf;
  std::int64_t Points;
  int WalksPerPoint;
  double Target;
  bool Announced = false;
  ProgressLabel Label;
};

// The run's summary in field data, ready to read in a spreadsheet view or
// a script.
void AddSummaryFields(vtkFieldData* fd, const BatchFindings& f, bool mixed, std::int64_t outside)
{
  const double walks = static_cast<double>(f.Walks);
  // The rate of the walks run now: resumed walks cost nothing.
  const double walksRun = static_cast<double>(f.WalksRun);
  AddFieldValue(fd, "TotalWalks", walks);
  AddFieldValue(fd, "TotalSteps", static_cast<double>(f.Steps));
  AddFieldValue(fd, "EscapedWalks", static_cast<double>(f.Escaped));
  AddFieldValue(fd, "TruncatedWalks", static_cast<double>(f.Truncated));
  AddFieldValue(fd, "SolveSeconds", f.Seconds);
  // Progressive refinement: walks per point taken from the kept sums.
  AddFieldValue(fd, "ResumedWalksPerPoint", static_cast<double>(f.ResumedWalksPerPoint));
  AddFieldValue(fd, "WalksRun", walksRun);
  if (f.Target > 0.0)
  {
    AddFieldValue(fd, "TargetStandardError", f.Target);
  }
  AddFieldValue(fd, "ProbePoints", static_cast<double>(f.Points));
  AddFieldValue(fd, "WalksPerSecond", f.Seconds > 0.0 ? walksRun / f.Seconds : 0.0);
  AddFieldValue(
    fd, "MeanStepsPerWalk", walks > 0.0 ? static_cast<double>(f.Steps) / walks : 0.0);
  AddFieldValue(
    fd, "EscapedWalkFraction", walks > 0.0 ? static_cast<double>(f.Escaped) / walks : 0.0);
  AddFieldValue(fd, "UnreliableErrorBars", static_cast<double>(f.UnreliableErrorBars));
  if (f.WalkOnWhereUnreliable > 1 && f.Target <= 0.0)
  {
    AddFieldValue(fd, "PointsWalkedOnForReliability", static_cast<double>(f.PointsWalkedOn));
  }
  if (mixed)
  {
    AddFieldValue(fd, "BackFaceHits", static_cast<double>(f.BackFaceHits));
    AddFieldValue(fd, "OutsidePoints", static_cast<double>(outside));
  }
}

// Points that took every walk allowed with a standard error still above
// the target. NaN values are not counted: more walks would not change them
// (points outside a closed boundary the problem solves inside, walks that
// overflowed, which their own warnings name).
std::int64_t PointsShortOfTarget(const EstimateArrays& arrays, double target, int walksPerPoint)
{
  const int nc = arrays.Components;
  std::int64_t unreached = 0;
  for (vtkIdType i = 0; i < arrays.Mean->GetNumberOfTuples(); ++i)
  {
    if (std::isnan(arrays.Mean->GetValue(i * nc)))
    {
      continue;
    }
    bool above = false;
    for (int c = 0; c < nc; ++c)
    {
      above = above || !(arrays.Variance->GetValue(i * nc + c) <= target * target);
    }
    unreached += (above && arrays.WalkCount->GetValue(i) >= walksPerPoint) ? 1 : 0;
  }
  return unreached;
}

// Where a batch's estimates go (Estimate's storage): VTK arrays, added to an
// output once at the end (unless it is null) ...
struct ArrayStorage
{
  static constexpr bool kClosestValues = true;
  EstimateArrays& Arrays;
  vtkPointData* Output;

  void Allocate(const std::string& name, int nc, vtkIdType n, bool biharmonic,
    const DerivativeRequest& derivatives)
  {
    this->Arrays.Allocate(name, nc, n, biharmonic, derivatives);
  }
  int Components() const { return this->Arrays.Components; }
  bool AnyDerivative() const { return this->Arrays.AnyDerivative; }
  void SetDistance(vtkIdType i, double d) { this->Arrays.Distance->SetValue(i, d); }
  void SetClosestValue(vtkIdType i, int c, double g)
  {
    this->Arrays.ClosestValue->SetTypedComponent(i, c, g);
  }
  // The walks at `points`, the probe's points `indices` (null: all of them).
  template <int DIM>
  BatchSummary Run(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& points,
    const BatchRequest& batch, ProgressReporter& progress, RunningSumsCache* kept,
    const std::vector<std::size_t>* indices)
  {
    const SampleLayout layout = problem.Layout(batch);
    auto storePoint = [&](std::size_t at, const RunningStatistics& stats,
                        const WalkCounters& counters, DerivativeStatus status)
    {
      this->Arrays.Store<DIM>(indices ? (*indices)[at] : at, stats, counters, layout,
        problem.ErrorBar(stats, counters, layout, status), status);
    };
    return problem.Estimate(points, batch, storePoint, std::ref(progress), kept);
  }
  template <int DIM>
  void StoreCached(const CacheAnswers& cached)
  {
    this->Arrays.StoreCached<DIM>(cached.Answers, cached.VarianceRelativeError);
  }
  void Finish(bool withWalkCount)
  {
    if (this->Output)
    {
      this->Arrays.AddTo(this->Output, withWalkCount);
    }
    else
    {
      this->Arrays.Finish();
    }
  }
  std::int64_t UnevenWeights() const { return this->Arrays.UnevenWeights.load(); }
  std::int64_t OneWalkSpread() const { return this->Arrays.OneWalkSpread.load(); }
  std::int64_t ShortOfTarget(double target, int walksPerPoint) const
  {
    return PointsShortOfTarget(this->Arrays, target, walksPerPoint);
  }
  double FirstValue(vtkIdType i) const
  {
    return this->Arrays.Mean->GetValue(i * this->Arrays.Components);
  }
};

// A batch run at some of the probe's points (`indices`), laid out over all
// `points` of the probe: the others NaN and not finished.
BatchEstimates ScatterBatch(const BatchEstimates& part, const std::vector<std::size_t>& indices,
  std::size_t points)
{
  BatchEstimates all;
  all.Summary = part.Summary;
  all.Points = points;
  const std::size_t size = static_cast<std::size_t>(part.Summary.Layout.Size);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  all.Means.assign(points * size, nan);
  all.Variances.assign(points * size, nan);
  all.Counters.assign(points, WalkCounters());
  all.Status.assign(points, DerivativeStatus::Unavailable);
  all.Finished.assign(points, 0);
  all.ErrorBars.assign(points, ErrorBarCheck());
  for (std::size_t k = 0; k < indices.size(); ++k)
  {
    const std::size_t i = indices[k];
    std::copy_n(part.Means.begin() + static_cast<std::ptrdiff_t>(k * size), size,
      all.Means.begin() + static_cast<std::ptrdiff_t>(i * size));
    std::copy_n(part.Variances.begin() + static_cast<std::ptrdiff_t>(k * size), size,
      all.Variances.begin() + static_cast<std::ptrdiff_t>(i * size));
    all.Counters[i] = part.Counters[k];
    all.Status[i] = part.Status[k];
    all.Finished[i] = part.Finished[k];
    all.ErrorBars[i] = part.ErrorBars[k];
  }
  return all;
}

// ... or the core's numbers (Problem::EstimateAll), for a filter that uses
// them itself.
struct NumberStorage
{
  static constexpr bool kClosestValues = false;
  PointNumbers& Numbers;

  void Allocate(const std::string&, int nc, vtkIdType n, bool, const DerivativeRequest& derivatives)
  {
    this->Numbers.Components = nc;
    this->Numbers.Request = derivatives;
    this->Numbers.Distance.assign(
      static_cast<std::size_t>(n), std::numeric_limits<double>::quiet_NaN());
  }
  int Components() const { return this->Numbers.Components; }
  bool AnyDerivative() const
  {
    const DerivativeRequest& r = this->Numbers.Request;
    return r.Gradient || r.Hessian || r.Directional;
  }
  void SetDistance(vtkIdType i, double d) { this->Numbers.Distance[static_cast<std::size_t>(i)] = d; }
  void SetClosestValue(vtkIdType, int, double) {}
  template <int DIM>
  BatchSummary Run(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& points,
    const BatchRequest& batch, ProgressReporter& progress, RunningSumsCache* kept,
    const std::vector<std::size_t>* indices)
  {
    this->Numbers.Dimension = DIM;
    this->Numbers.Batch = problem.EstimateAll(points, batch, std::ref(progress), kept);
    if (indices)
    {
      this->Numbers.Batch = ScatterBatch(this->Numbers.Batch, *indices, this->Numbers.Distance.size());
    }
    return this->Numbers.Batch.Summary;
  }
  // The cache's answers in the slots of the value and the gradient, as
  // finished points with no walks.
  template <int DIM>
  void StoreCached(const CacheAnswers& cached)
  {
    BatchEstimates& b = this->Numbers.Batch;
    const SampleLayout& layout = b.Summary.Layout;
    const std::size_t size = static_cast<std::size_t>(layout.Size);
    const int nc = this->Numbers.Components;
    const CacheEvaluation& e = cached.Answers;
    for (std::size_t i = 0; i < b.Points; ++i)
    {
      if (!std::isfinite(e.Value[i * nc]))
      {
        continue;
      }
      b.Finished[i] = 1;
      b.Status[i] = DerivativeStatus::Interior;
      b.Counters[i] = WalkCounters();
      b.ErrorBars[i] = ErrorBarCheck();
      for (int c = 0; c < nc; ++c)
      {
        b.Means[i * size + layout.Value + c] = e.Value[i * nc + c];
        b.Variances[i * size + layout.Value + c] = e.ValueVariance[i * nc + c];
        for (int a = 0; a < DIM && layout.Gradient >= 0 && !e.Gradient.empty(); ++a)
        {
          const std::size_t slot = static_cast<std::size_t>(layout.Gradient + c * DIM + a);
          b.Means[i * size + slot] = e.Gradient[(i * nc + c) * DIM + a];
          b.Variances[i * size + slot] = e.GradientVariance[(i * nc + c) * DIM + a];
        }
        if (c == 0 && layout.Divergence >= 0 && !e.Divergence.empty())
        {
          b.Means[i * size + static_cast<std::size_t>(layout.Divergence)] = e.Divergence[i];
          b.Variances[i * size + static_cast<std::size_t>(layout.Divergence)] =
            e.DivergenceVariance[i];
          for (std::size_t a = 0; a < 3; ++a)
          {
            const std::size_t slot = static_cast<std::size_t>(layout.Curl) + a;
            b.Means[i * size + slot] = e.Curl[3 * i + a];
            b.Variances[i * size + slot] = e.CurlVariance[3 * i + a];
          }
        }
        if (layout.Directional >= 0 && !e.Directional.empty())
        {
          const std::size_t slot = static_cast<std::size_t>(layout.Directional + c);
          b.Means[i * size + slot] = e.Directional[i * nc + c];
          b.Variances[i * size + slot] = e.DirectionalVariance[i * nc + c];
        }
        for (int a = 0; a < DIM * DIM && layout.Hessian >= 0 && !e.Hessian.empty(); ++a)
        {
          const std::size_t slot = static_cast<std::size_t>(layout.Hessian + c * DIM * DIM + a);
          b.Means[i * size + slot] = e.Hessian[(i * nc + c) * DIM * DIM + a];
          b.Variances[i * size + slot] = e.HessianVariance[(i * nc + c) * DIM * DIM + a];
        }
      }
    }
  }
  void Finish(bool) {}
  // As EstimateArrays::Store counts them, over the points that reached it.
  std::int64_t UnevenWeights() const { return this->CountErrorBars(true); }
  std::int64_t OneWalkSpread() const { return this->CountErrorBars(false); }
  std::int64_t ShortOfTarget(double target, int walksPerPoint) const
  {
    const BatchEstimates& b = this->Numbers.Batch;
    std::int64_t unreached = 0;
    for (std::size_t i = 0; i < b.Points; ++i)
    {
      if (std::isnan(b.Value(i)))
      {
        continue; // as PointsShortOfTarget
      }
      bool above = false;
      for (int c = 0; c < this->Numbers.Components; ++c)
      {
        above = above || !(b.ValueVariance(i, c) <= target * target);
      }
      const auto walks = std::min<std::uint64_t>(b.Counters[i].Walks, VTK_INT_MAX);
      unreached += (above && static_cast<int>(walks) >= walksPerPoint) ? 1 : 0;
    }
    return unreached;
  }
  double FirstValue(vtkIdType i) const
  {
    return this->Numbers.Value(static_cast<std::size_t>(i));
  }

private:
  std::int64_t CountErrorBars(bool uneven) const
  {
    const BatchEstimates& b = this->Numbers.Batch;
    std::int64_t count = 0;
    for (std::size_t i = 0; i < b.Points; ++i)
    {
      if (!b.Finished[i])
      {
        continue;
      }
      const ErrorBarCheck& check = b.ErrorBars[i];
      count += !check.Reliable && check.UnevenWeights == uneven ? 1 : 0;
    }
    return count;
  }
};

// The batch at `probePoints`: the request from the settings, the run, the
// estimates into `arrays` (its storage), the summary and the warnings.
template <int DIM, class Storage>
bool Estimate(vtkAlgorithm* self, const BuiltProblem& built, const SolveSettings& s,
  const std::vector<std::array<double, 3>>& probePoints, Storage arrays, vtkPointData* pd,
  vtkFieldData* fd, const PointEstimateRun& run, PointEstimateSummary& result)
{
  const Problem<DIM>& problem = built.Get<DIM>();
  const bool mixed = problem.GetMixedBoundary() != nullptr;
  const int nc = built.Components;
  const Warn warn = [&run](const std::string& text)
  {
    if (run.Warn)
    {
      run.Warn(text);
    }
  };
  const std::string name = SolutionName(built.Name, pd, warn);
  StartPoints<DIM> start;
  start.Find(problem, probePoints, warn);
  const std::vector<std::array<double, 3>>& points = start.Of(probePoints, mixed);
  const auto numPoints = static_cast<vtkIdType>(probePoints.size());

  const bool cacheChosen = s.Estimator != Estimator::PointwiseWalks && built.Caches;
  const DerivativeRequest derivatives = DerivativesOf(s, nc, cacheChosen);
  arrays.Allocate(name, nc, numPoints, built.Biharmonic, derivatives);
  FillBoundaryArrays<DIM>(problem, points, arrays);

  BatchRequest batch;
  if (!MakeBatchRequest(self, s, built, derivatives, batch))
  {
    result.Completed = false;
    return false;
  }
  const double target = batch.TargetStandardError;

  // A cache estimator: the cache answers the points clear of the boundary's
  // shell (building or growing it takes the first part of the progress),
  // walks answer the others.
  CacheAnswers cached;
  PointEstimateRun walkRun = run;
  if (cacheChosen)
  {
    PointEstimateRun cacheRun = run;
    cacheRun.ProgressEnd = walkRun.ProgressBegin =
      run.ProgressBegin + 0.8 * (run.ProgressEnd - run.ProgressBegin);
    ProgressReporter cacheProgress(self, cacheRun, warn, numPoints, s.WalksPerCachePoint, 0.0);
    CacheDerivatives want(derivatives.Gradient);
    want.Hessian = derivatives.Hessian;
    want.Directional = derivatives.Directional;
    want.Direction = derivatives.Direction;
    want.DivergenceCurl = derivatives.DivergenceCurl;
    if (!AnswerFromCache<DIM>(self, built, s, points, want, target,
          run.KeepGrownCaches, std::ref(cacheProgress), cached))
    {
      result.Completed = false;
      if (self->GetAbortExecute())
      {
        // Aborted while the cache walked: the arrays, every point NaN (zero
        // derivatives), so that filters downstream still find them; the
        // cache keeps the walks it finished, and the next update continues.
        arrays.Finish(true);
        warn("The solve was aborted while the cache's walks ran: every point is NaN. Apply "
             "again to continue (the walks the cache finished are kept).");
      }
      return false;
    }
    WarnOfPointsOutside(cached.Outside, numPoints, warn);
  }
  const std::vector<std::array<double, 3>>& walked = cached.Active ? cached.WalkedPoints : points;

  // Progressive refinement: the batch continues from the running sums the
  // caller kept (it forgot them if anything but WalksPerPoint changed) and
  // keeps its own.
  ProgressReporter progress(self, walkRun, warn, numPoints, batch.WalksPerPoint, target);
  const BatchSummary summary = arrays.template Run<DIM>(
    problem, walked, batch, progress, run.Kept, cached.Active ? &cached.Walked : nullptr);
  if (cached.Active)
  {
    arrays.template StoreCached<DIM>(cached);
  }

  // Walks run now; the output stands for the totals (kept walks included).
  result.ResumedWalksPerPoint = summary.ResumedWalksPerPoint;
  // (The boundary cache's walks and seconds count too: its field data
  // tell them apart.)
  result.WalksRun = summary.WalksRun + cached.WalksRun;
  result.Seconds = summary.Seconds + cached.Seconds;
  result.Completed = summary.Completed;
  result.PointsFinished = static_cast<std::int64_t>(summary.PointsFinished);
  result.PointsWithoutWalks = static_cast<std::int64_t>(summary.PointsWithoutWalks);
  result.UnreliableErrorBars = static_cast<std::int64_t>(summary.UnreliableErrorBars);
  // WalkCount where the points' counts differ.
  arrays.Finish(
    target > 0.0 || !summary.Completed || cached.Active || summary.PointsWalkedOn > 0);

  BatchFindings found;
  found.Name = name;
  found.Points = numPoints;
  found.WalksPerPoint = batch.WalksPerPoint;
  found.MaxSteps = s.MaxSteps;
  found.Target = target;
  found.ResumedWalksPerPoint = summary.ResumedWalksPerPoint;
  found.Completed = summary.Completed;
  found.Seconds = summary.Seconds;
  found.Biharmonic = built.Biharmonic;
  found.AnyDerivative = arrays.AnyDerivative();
  found.UnboundedSource = summary.UnboundedSource;
  found.PointsFinished = summary.PointsFinished;
  found.PointsWithoutWalks = summary.PointsWithoutWalks;
  found.BackFaceHits = summary.BackFaceHits;
  found.PointsOutsideShift = summary.PointsOutsideShift;
  found.UnreliableErrorBars = summary.UnreliableErrorBars;
  found.WalkOnWhereUnreliable = batch.WalkOnWhereUnreliable;
  found.PointsWalkedOn = summary.PointsWalkedOn;
  found.UnevenWeights = arrays.UnevenWeights();
  found.OneWalkSpread = arrays.OneWalkSpread();
  found.Walks = summary.Totals.Walks;
  found.WalksRun = summary.WalksRun;
  found.Steps = summary.Totals.Steps;
  found.Escaped = summary.Totals.Escaped;
  found.Truncated = summary.Totals.Truncated;
  found.Returns = summary.Totals.Returns;
  found.StatusCounts = summary.StatusCounts;
  if (fd)
  {
    AddSummaryFields(fd, found, mixed, start.Outside);
    if (problem.GetSources() && !problem.GetSources()->Empty() &&
      WalkOnSpheresEstimator<DIM>::UsesSources(problem.Settings().Problem))
    {
      // The source sampling the walks took (Automatic decided by now).
      AddFieldValue(fd, "SourceSamplingUsed", static_cast<double>(problem.Settings().Sampling));
    }
    if (const PolynomialShift<DIM>* shift = problem.GetPolynomialShift())
    {
      // The walks estimated u − P: the degree of P, and the points outside
      // the closed boundary it left NaN.
      AddFieldValue(fd, "PolynomialControlVariate", static_cast<double>(shift->GetDegree()));
      AddFieldValue(fd, "OutsideControlVariate", static_cast<double>(summary.PointsOutsideShift));
    }
    if (cached.Active)
    {
      AddCacheFields(fd, cached, start.Outside);
    }
  }
  DebugSummary(self, found);
  if (summary.Completed)
  {
    if (target > 0.0)
    {
      found.PointsShortOfTarget =
        arrays.ShortOfTarget(target, batch.WalksPerPoint) + cached.ShortOfTarget;
      result.PointsShortOfTarget = found.PointsShortOfTarget;
      if (fd)
      {
        AddFieldValue(fd, "PointsShortOfTarget", static_cast<double>(found.PointsShortOfTarget));
      }
    }
    // NaN results of finite probe points: walks whose coordinates
    // overflowed (points far beyond the boundary's scale) end with no
    // boundary value.
    found.NanResults = -start.NonFinite - start.Outside - cached.Outside -
      static_cast<std::int64_t>(summary.PointsOutsideShift);
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      found.NanResults += std::isnan(arrays.FirstValue(i)) ? 1 : 0;
    }
  }
  BatchWarningChoice choice;
  choice.ShortOfTarget = run.ReportShortOfTarget;
  choice.UnreliableErrorBars = run.ReportUnreliableErrorBars;
  WarnAboutBatch(self, found, choice, warn);
  return summary.Completed;
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
  PointEstimateSummary& summary, EstimateArrays* keep)
{
  EstimateArrays local;
  const ArrayStorage storage{ keep ? *keep : local, arrays };
  summary = PointEstimateSummary();
  return problem.Dimension == 2
    ? Estimate<2>(reporter, problem, settings, points, storage, arrays, fieldData, run, summary)
    : Estimate<3>(reporter, problem, settings, points, storage, arrays, fieldData, run, summary);
}

bool EstimateNumbersAtPoints(vtkAlgorithm* reporter, const BuiltProblem& problem,
  const SolveSettings& settings, const std::vector<std::array<double, 3>>& points,
  PointNumbers& numbers, const PointEstimateRun& run, PointEstimateSummary& summary)
{
  const NumberStorage storage{ numbers };
  summary = PointEstimateSummary();
  return problem.Dimension == 2
    ? Estimate<2>(reporter, problem, settings, points, storage, nullptr, nullptr, run, summary)
    : Estimate<3>(reporter, problem, settings, points, storage, nullptr, nullptr, run, summary);
}
} // namespace gridfree
