// A problem built once and answered in batches: the boundary (geometry,
// hierarchy and values), the equation and its settings, and the sources.
// This is the one door into the estimators for the VTK filters and for any
// C++ program: build a Problem when the boundary or the equation changes,
// then ask it for estimates at any list of points, as often as needed,
// without rebuilding anything.
//
// A batch runs every point's walks on all threads (TBB) while the calling
// thread reports progress and polls for abort. The numbers depend only on
// the seed, each point's coordinates and the walk numbers, never on the
// thread count: points are independent, and with fewer points than twice
// the threads each point's walks are spread over the threads in blocks whose
// samples are recorded and replayed in walk order. A batch may resume from
// running sums kept by the previous one (progressive refinement, paper Sec.
// 5.2; RunningSumsCache.h), bit for bit as if all walks ran at once.
#ifndef GRIDFREE_PROBLEM_PROBLEM_H
#define GRIDFREE_PROBLEM_PROBLEM_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/problem/PointWalks.h>
#include <gridfree/sources/SourceSet.h>
#include <gridfree/stars/WalkOnStars.h>
#include <gridfree/statistics/ErrorBarReliability.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/statistics/RunningSumsCache.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <utility>
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
  // Walk on stars: rays that met the Neumann or Robin part from outside
  // (WalkOnStarsEstimator::BackFaceHits), the sign of a wrongly oriented or
  // leaking reflecting surface; 0 otherwise.
  std::uint64_t BackFaceHits = 0;
  // Points that ran all their walks (every point of a complete batch); an
  // aborted batch with kept sums hands the others to the sink with the
  // walks they hold, but for PointsWithoutWalks, which hold none.
  std::uint64_t PointsFinished = 0;
  std::uint64_t PointsWithoutWalks = 0;
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

template <int DIM>
class Problem
{
public:
  // Throws std::invalid_argument for a problem no walk can solve (no
  // boundary, ε not positive, a screened equation without screening, a
  // biharmonic boundary without g and h).
  Problem(std::shared_ptr<const Boundary<DIM>> boundary, const WalkSettings& settings,
    std::shared_ptr<const SourceSet<DIM>> sources = nullptr)
    : Shape(std::move(boundary))
    , Walk(settings)
    , Sources(std::move(sources))
  {
    this->Initialize();
  }

  // A problem with Neumann or Robin conditions on part of the boundary,
  // solved by walk on stars (WalkOnStars.h): value batches only (a request
  // for derivatives throws std::invalid_argument). Also throws for what
  // walk on stars cannot solve (the biharmonic equation; Neumann
  // conditions alone without screening).
  Problem(std::shared_ptr<const MixedBoundary<DIM>> mixed, const WalkSettings& settings,
    std::shared_ptr<const SourceSet<DIM>> sources = nullptr)
    : Shape(mixed ? (mixed->HasDirichlet() ? mixed->SharedDirichlet() : mixed->SharedReflecting())
                  : nullptr)
    , Mixed(std::move(mixed))
    , Walk(settings)
    , Sources(std::move(sources))
  {
    this->Initialize();
    // The estimator's own checks, once, here rather than on a worker thread.
    WalkOnStarsEstimator<DIM> check(*this->Mixed, this->Walk);
    (void)check;
  }

  // The mixed boundary of a walk-on-stars problem, or null.
  const MixedBoundary<DIM>* GetMixedBoundary() const { return this->Mixed.get(); }

private:
  void Initialize()
  {
    if (!this->Shape || this->Shape->Empty())
    {
      throw std::invalid_argument("the problem has no boundary");
    }
    if (!(this->Walk.Epsilon > 0.0))
    {
      throw std::invalid_argument("epsilon must be positive");
    }
    if (this->Walk.Problem == Equation::Biharmonic && this->Shape->Components() % 2 != 0)
    {
      throw std::invalid_argument("biharmonic boundary values must hold g and h");
    }
    if (this->Walk.Problem == Equation::ScreenedPoisson && !(this->Walk.ScreeningCoefficient > 0.0))
    {
      throw std::invalid_argument("the screening coefficient must be positive");
    }
    // A mixed problem's flux makes its values vary even with constant g.
    this->ConstantData = !this->Mixed && this->Shape->ConstantValues() &&
      (!this->Sources || this->Sources->Empty());
    this->BuildSourceDensity();
  }

public:

  const Boundary<DIM>& GetBoundary() const { return *this->Shape; }
  const std::shared_ptr<const Boundary<DIM>>& SharedBoundary() const { return this->Shape; }
  const WalkSettings& Settings() const { return this->Walk; }
  const SourceSet<DIM>* GetSources() const { return this->Sources.get(); }

  // Components of the solution (g's, or half of g and h's for the
  // biharmonic equation).
  int SolutionComponents() const
  {
    return this->Walk.Problem == Equation::Biharmonic ? this->Shape->Components() / 2
                                                      : this->Shape->Components();
  }

  // The slots of each point's statistics for this request: the value (and
  // Δu for the biharmonic equation) first, then the derivatives asked for.
  SampleLayout Layout(const BatchRequest& request) const
  {
    if (request.DerivativeWalks() && this->Mixed)
    {
      throw std::invalid_argument(
        "derivatives are not estimated with Neumann or Robin conditions (walk on stars) yet");
    }
    if (request.DerivativeWalks())
    {
      auto volume = this->MakeVolume();
      return DerivativeWalkOnSpheres<DIM>(
        *this->Shape, this->Walk, request.Derivatives, volume.get(), this->Concentrated())
        .Layout();
    }
    SampleLayout layout;
    const int nc = this->SolutionComponents();
    layout.Value = 0;
    layout.Laplacian = this->Walk.Problem == Equation::Biharmonic ? nc : -1;
    // Walk on stars' screened walks keep no weight slot (their weights
    // fall at Neumann and Robin hits as well as on spheres).
    layout.Weight = this->Walk.Problem == Equation::ScreenedPoisson && !this->Mixed ? nc : -1;
    layout.Size = this->Walk.Problem == Equation::Biharmonic ? 2 * nc
      : layout.Weight >= 0                                   ? nc + 1
                                                             : nc;
    return layout;
  }

  // Whether a finished point's error bar can be trusted, from its
  // statistics and counters (ErrorBarReliability.h): what the sink can
  // report per point.
  ErrorBarCheck ErrorBar(
    const RunningStatistics& stats, const WalkCounters& counters, const SampleLayout& layout) const
  {
    return CheckErrorBar(stats, layout.Value, this->SolutionComponents(), layout.Weight,
      this->SpreadPossible(counters));
  }

  // Whether the walks of a point with these counters could have given
  // different values: they took steps, and the data are not constant.
  bool SpreadPossible(const WalkCounters& counters) const
  {
    return counters.Steps > 0 && !this->ConstantData;
  }

  // Runs request.WalksPerPoint walks at every point (the first DIM of its
  // three coordinates are the start point; all three key its random
  // streams) and hands each finished point to `sink`. With `kept`, the batch
  // continues from the sums it holds when they fit (same points, same
  // layout, no more walks than asked, a target that allows it:
  // RunningSumsCache::CanResume), each point from its own walk count, and
  // keeps its own; the caller clears `kept` when anything else changed.
  // Aborted with `kept`, the batch still hands every point that holds walks
  // to `sink` (those cut short with the walks they ran, those not reached
  // with the kept ones) and keeps them all, so that the next batch
  // continues where this one stopped; points without any walk never reach
  // `sink`. Exceptions of the estimators propagate.
  BatchSummary Estimate(const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request, const PointSink& sink,
    const BatchProgressCallback& progress = BatchProgressCallback(),
    RunningSumsCache* kept = nullptr) const
  {
    BatchSummary summary;
    const bool derivativeWalks = request.DerivativeWalks();
    summary.Layout = this->Layout(request);
    const int sampleSize = summary.Layout.Size;
    const std::size_t numPoints = points.size();
    const int walks = std::max(0, request.WalksPerPoint);
    const std::uint64_t seed = request.Seed;

    // Progressive refinement: continue from the kept sums and keep this
    // batch's, with the derivative estimator's control-block history, so
    // that the next batch can continue from any walk count.
    const int blockWalks = derivativeWalks ? DerivativeWalkOnSpheres<DIM>::kControlBlock : 64;
    const double target = request.TargetStandardError;
    const bool resumed = kept &&
      kept->CanResume(
        numPoints, sampleSize, derivativeWalks, target, static_cast<std::uint64_t>(walks));
    if (kept && !resumed)
    {
      kept->Reset(numPoints, sampleSize, derivativeWalks, target, this->SolutionComponents());
    }
    // A tighter target than the kept sums': their stopped points are checked again.
    const bool tighterTarget = resumed && target > 0.0 && target < kept->KeptTarget();
    if (resumed)
    {
      kept->Retarget(target);
    }
    // Every point holds the same walks unless an abort (or a target) left
    // them uneven; each point continues from its own count.
    const bool uniformStart = !resumed || kept->Uniform();
    const int startWalks = resumed ? static_cast<int>(kept->KeptWalks()) : 0;
    // After an abort, the walks every point resumed from.
    summary.ResumedWalksPerPoint = !resumed ? 0
      : kept->Interrupted()                 ? static_cast<int>(kept->FewestWalks())
                                            : startWalks;
    auto startPoint = [&](std::size_t i, RunningStatistics& stats, WalkCounters& counters,
                        unsigned char& status) {
      stats.Reset();
      counters = WalkCounters();
      status = 0;
      if (resumed)
      {
        kept->Load(i, stats, counters, status);
      }
    };

    const int valueComponents = this->SolutionComponents();
    const int threadCount = ResolveThreadCount(request.Threads);
    // Walk-level blocks follow the control blocks (multiples of blockWalks);
    // a batch resumed inside one starts with the rest of that block.
    const int leadWalks =
      std::min((blockWalks - startWalks % blockWalks) % blockWalks, walks - startWalks);
    const std::size_t blocksPerPoint = static_cast<std::size_t>(leadWalks > 0) +
      static_cast<std::size_t>((walks - startWalks - leadWalks + blockWalks - 1) / blockWalks);
    const bool walkLevel = target <= 0.0 && uniformStart && threadCount > 1 &&
      numPoints < 2 * static_cast<std::size_t>(threadCount) &&
      blocksPerPoint > 1 &&
      static_cast<double>(numPoints) * (walks - startWalks) * sampleSize <= 16.0 * 1024 * 1024;

    const auto start = std::chrono::steady_clock::now();
    double totalWalks = 0.0;
    if (uniformStart)
    {
      totalWalks = static_cast<double>(numPoints) * static_cast<double>(walks - startWalks);
    }
    else
    {
      for (std::size_t i = 0; i < numPoints; ++i)
      {
        totalWalks += static_cast<double>(walks) - static_cast<double>(kept->Walks(i));
      }
    }
    std::atomic<std::uint64_t> walksDone{ 0 };
    auto report = [&](double fraction) {
      if (!progress)
      {
        return true;
      }
      BatchProgress p;
      p.WalksRun = walksDone.load(std::memory_order_relaxed);
      p.WalksToRun = totalWalks;
      p.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      p.PointsFraction = fraction;
      p.Fraction = std::max(
        fraction, totalWalks > 0.0 ? std::min(1.0, static_cast<double>(p.WalksRun) / totalWalks) : 1.0);
      return progress(p);
    };

    std::atomic<std::uint64_t> backFaceHits{ 0 };
    std::mutex totalsMutex;
    auto addTotals = [&](const WalkCounters& sum, const std::array<std::uint64_t, 3>& counts,
                       bool bounded, std::uint64_t unreliable) {
      std::lock_guard<std::mutex> lock(totalsMutex);
      summary.Totals.Add(sum);
      summary.UnreliableErrorBars += unreliable;
      for (int k = 0; k < 3; ++k)
      {
        summary.StatusCounts[k] += counts[k];
      }
      summary.UnboundedSource = summary.UnboundedSource || !bounded;
    };

    // Points handed to the sink (an abort leaves some out; counted with or
    // without kept sums).
    std::vector<unsigned char> sunk(numPoints, 0);
    std::atomic<std::uint64_t> finished{ 0 };
    if (walkLevel)
    {
      summary.Completed = this->EstimateByBlocks(points, request, sink, kept, startPoint,
        startWalks, leadWalks, blockWalks, blocksPerPoint, sampleSize, walksDone, backFaceHits,
        report, addTotals, sunk, finished);
    }
    else
    {
      summary.Completed = ParallelForWithProgress(
        numPoints, request.Threads,
        [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
          auto volume = this->MakeVolume();
          WalkCounters sum;
          std::array<std::uint64_t, 3> counts = { 0, 0, 0 };
          std::uint64_t unreliable = 0;
          auto runPoints = [&](auto& estimator) {
            RunningStatistics stats(sampleSize, valueComponents);
            for (std::size_t i = begin; i < end && !cancel.load(std::memory_order_relaxed); ++i)
            {
              WalkCounters counters;
              unsigned char keptStatus = 0;
              startPoint(i, stats, counters, keptStatus);
              auto status = static_cast<DerivativeStatus>(keptStatus);
              // The walks of a fixed count, or those a target needs, either
              // continuing from kept sums; then keeping them.
              auto runWalks = [&]() {
                using Estimator = std::decay_t<decltype(estimator)>;
                if constexpr (PointWalks::HasContinueBlock<Estimator>::value)
                {
                  if (resumed)
                  {
                    kept->LoadHistory(i, estimator.BlockHistory());
                  }
                }
                bool stopped = resumed && kept->Stopped(i);
                if (stopped && tighterTarget)
                {
                  // Stopped at a looser target: it stays stopped only if
                  // it meets this one where it stands.
                  stopped = PointWalks::MeetsTarget(stats, counters, target, valueComponents,
                    summary.Layout.Weight, !this->ConstantData);
                }
                // The point's own count: kept sums differ after an abort.
                const int from = static_cast<int>(stats.SampleCount());
                bool ran = true;
                if (target > 0.0)
                {
                  ran = stopped ||
                    PointWalks::EstimateToTarget(estimator, points[i].data(), seed, from, walks, target,
                      valueComponents, summary.Layout.Weight, !this->ConstantData, stats,
                      counters, cancel, walksDone, status, stopped);
                }
                else
                {
                  ran = PointWalks::EstimateInChunks(estimator, points[i].data(), seed, from, walks, stats,
                    counters, cancel, walksDone, status, from > 0);
                }
                // Kept also when cut short: the next batch continues from
                // the walks it ran (whole chunks, with their history).
                if (kept)
                {
                  kept->Save(i, stats, counters, static_cast<unsigned char>(status), stopped);
                  if constexpr (PointWalks::HasContinueBlock<Estimator>::value)
                  {
                    kept->SaveHistory(i, estimator.BlockHistory());
                  }
                }
                return ran;
              };
              const bool ran = runWalks();
              if (!ran && !(kept && stats.SampleCount() > 0))
              {
                return; // aborted before this point's first walk: it never reaches the sink
              }
              finished.fetch_add(ran ? 1 : 0, std::memory_order_relaxed);
              if (derivativeWalks)
              {
                counts[static_cast<int>(status)] += 1;
              }
              sum.Add(counters);
              unreliable += this->ErrorBar(stats, counters, summary.Layout).Reliable ? 0 : 1;
              sink(i, stats, counters, status);
              sunk[i] = 1;
              if (!ran)
              {
                return; // aborted: the points after this one are not reached
              }
            }
          };
          bool bounded = true;
          if (derivativeWalks)
          {
            DerivativeWalkOnSpheres<DIM> estimator(
              *this->Shape, this->Walk, request.Derivatives, volume.get(), this->Concentrated());
            runPoints(estimator);
            bounded = estimator.SourceSupportIsBounded();
          }
          else if (this->Mixed)
          {
            WalkOnStarsEstimator<DIM> estimator(
              *this->Mixed, this->Walk, volume.get(), this->Concentrated());
            runPoints(estimator);
            backFaceHits.fetch_add(estimator.BackFaceHits(), std::memory_order_relaxed);
          }
          else
          {
            WalkOnSpheresEstimator<DIM> estimator(
              *this->Shape, this->Walk, volume.get(), this->Concentrated());
            runPoints(estimator);
            bounded = estimator.SourceSupportIsBounded();
          }
          addTotals(sum, counts, bounded, unreliable);
        },
        report);
    }
    if (kept && !summary.Completed)
    {
      // The points the abort left out, with the walks kept for them.
      RunningStatistics stats(sampleSize, valueComponents);
      WalkCounters sum;
      std::array<std::uint64_t, 3> counts = { 0, 0, 0 };
      std::uint64_t unreliable = 0;
      for (std::size_t i = 0; i < numPoints; ++i)
      {
        if (sunk[i])
        {
          continue;
        }
        WalkCounters counters;
        unsigned char status = 0;
        startPoint(i, stats, counters, status);
        if (stats.SampleCount() == 0)
        {
          continue;
        }
        if (derivativeWalks)
        {
          counts[status] += 1;
        }
        sum.Add(counters);
        unreliable += this->ErrorBar(stats, counters, summary.Layout).Reliable ? 0 : 1;
        sink(i, stats, counters, static_cast<DerivativeStatus>(status));
        sunk[i] = 1;
      }
      addTotals(sum, counts, true, unreliable);
    }
    summary.PointsFinished = summary.Completed ? numPoints : finished.load();
    summary.PointsWithoutWalks = 0;
    for (std::size_t i = 0; i < sunk.size() && !summary.Completed; ++i)
    {
      summary.PointsWithoutWalks += sunk[i] ? 0 : 1;
    }
    summary.WalksRun = walksDone.load();
    summary.BackFaceHits = backFaceHits.load();
    summary.Seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (kept)
    {
      if (summary.Completed && walks > 0)
      {
        // A target batch's points stop at different counts.
        kept->SetKeptWalks(static_cast<std::uint64_t>(walks), target <= 0.0);
      }
      else
      {
        kept->KeepWhatEachPointHolds();
      }
    }
    return summary;
  }

  // Estimate, with every point's means and variances collected.
  BatchEstimates EstimateAll(const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request,
    const BatchProgressCallback& progress = BatchProgressCallback(),
    RunningSumsCache* kept = nullptr) const
  {
    BatchEstimates out;
    out.Points = points.size();
    const std::size_t size = static_cast<std::size_t>(this->Layout(request).Size);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.Means.assign(out.Points * size, nan);
    out.Variances.assign(out.Points * size, nan);
    out.Counters.assign(out.Points, WalkCounters());
    out.Status.assign(out.Points, DerivativeStatus::Unavailable);
    out.Finished.assign(out.Points, 0);
    out.ErrorBars.assign(out.Points, ErrorBarCheck());
    const SampleLayout layout = this->Layout(request);
    out.Summary = this->Estimate(points, request,
      [this, &out, &layout, size](std::size_t i, const RunningStatistics& stats,
        const WalkCounters& counters, DerivativeStatus status) {
        for (std::size_t s = 0; s < size; ++s)
        {
          out.Means[i * size + s] = stats.GetMean(static_cast<int>(s));
          out.Variances[i * size + s] = stats.VarianceOfMean(static_cast<int>(s));
        }
        out.Counters[i] = counters;
        out.Status[i] = status;
        out.Finished[i] = 1;
        out.ErrorBars[i] = this->ErrorBar(stats, counters, layout);
      },
      progress, kept);
    return out;
  }

private:
  std::unique_ptr<VolumeSource<DIM>> MakeVolume() const
  {
    return this->Sources && this->Sources->MakeVolume
      ? this->Sources->MakeVolume(this->DomainBox().Diagonal())
      : nullptr;
  }

  // The box of the whole boundary (both parts of a mixed one).
  BoundingBox<DIM> DomainBox() const
  {
    return this->Mixed ? this->Mixed->Bounds()
                       : BoundingBox<DIM>(this->Shape->BoundsMin(), this->Shape->BoundsMax());
  }

  ConcentratedSourceSet<DIM> Concentrated() const
  {
    ConcentratedSourceSet<DIM> set =
      this->Sources ? this->Sources->Concentrated() : ConcentratedSourceSet<DIM>();
    set.VolumeDensity = this->Density.get();
    return set;
  }

  // Source-density sampling's map of |f| (SourceDensityMap.h), over the
  // source's support within the boundary's box (walks inside the domain
  // never leave it), or over the support alone when they do not meet
  // (exterior problems), or the boundary's box for an unbounded support.
  void BuildSourceDensity()
  {
    if (this->Walk.Sampling != SourceSampling::SourceDensity || !this->Sources ||
      !this->Sources->MakeVolume || !WalkOnSpheresEstimator<DIM>::UsesSources(this->Walk.Problem))
    {
      return;
    }
    auto volume = this->MakeVolume();
    if (!volume)
    {
      return;
    }
    const BoundingBox<DIM> domain = this->DomainBox();
    BoundingBox<DIM> box = domain;
    Vec<DIM> lo, hi;
    if (volume->SupportBounds(lo, hi))
    {
      const BoundingBox<DIM> inside(lo.cwiseMax(domain.Min), hi.cwiseMin(domain.Max));
      box = inside.IsEmpty() ? BoundingBox<DIM>(lo, hi) : inside;
    }
    auto map = std::make_shared<SourceDensityMap<DIM>>();
    map->Build(*volume, this->Shape->Components(), box);
    this->Density = std::move(map);
  }


  // Few points, several threads: each point's walks in blocks spread over
  // the threads, each block recorded and then replayed in walk order, so the
  // numbers are bit for bit those of one thread. Blocks of the derivative
  // estimator are its control blocks, whose control variates only use the
  // walks before them in the same block: a batch resumed inside a block
  // starts with its remaining `leadWalks` walks, continuing from the kept
  // history, and keeps the history of each point's last block.
  template <class StartPoint, class Report, class AddTotals>
  bool EstimateByBlocks(const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request, const PointSink& sink, RunningSumsCache* kept,
    const StartPoint& startPoint, int startWalks, int leadWalks, int blockWalks,
    std::size_t blocksPerPoint, int sampleSize, std::atomic<std::uint64_t>& walksDone,
    std::atomic<std::uint64_t>& backFaceHits, const Report& report,
    const AddTotals& addTotals, std::vector<unsigned char>& sunk,
    std::atomic<std::uint64_t>& finished) const
  {
    const bool derivativeWalks = request.DerivativeWalks();
    const int walks = request.WalksPerPoint;
    const std::size_t numPoints = points.size();
    const std::size_t items = numPoints * blocksPerPoint;
    std::vector<SampleRecorder> recorders(items, SampleRecorder(sampleSize));
    std::vector<WalkCounters> blockCounters(items);
    std::vector<char> blockDone(items, 0);
    std::vector<DerivativeStatus> pointStatus(numPoints, DerivativeStatus::Interior);
    // Each point's history after its last block, kept only if all its
    // blocks ran (an abort must not pair it with the older sums).
    std::vector<RunningStatistics> lastHistory(
      kept && derivativeWalks ? numPoints : 0, RunningStatistics(sampleSize));
    std::atomic<bool> unbounded{ false };
    const bool completed = ParallelForWithProgress(
      items, request.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
        auto volume = this->MakeVolume();
        auto runBlocks = [&](auto& estimator) {
          for (std::size_t item = begin; item < end && !cancel.load(std::memory_order_relaxed);
               ++item)
          {
            const std::size_t i = item / blocksPerPoint;
            const int b = static_cast<int>(item % blocksPerPoint);
            const int first = b == 0 ? startWalks
                                     : startWalks + leadWalks + (b - (leadWalks > 0)) * blockWalks;
            const int count = b == 0 && leadWalks > 0 ? leadWalks : std::min(blockWalks, walks - first);
            using Estimator = std::decay_t<decltype(estimator)>;
            if constexpr (PointWalks::HasContinueBlock<Estimator>::value)
            {
              // Only a resumed point's first, partial block continues a block.
              const bool continuing = b == 0 && leadWalks > 0 && kept && startWalks > 0;
              if (continuing)
              {
                kept->LoadHistory(i, estimator.BlockHistory());
              }
              estimator.ContinueBlock(continuing);
            }
            recorders[item].Reserve(static_cast<std::size_t>(count));
            using Result = decltype(estimator.EstimatePoint(points[i].data(), request.Seed,
              std::uint64_t(0), count, recorders[item], blockCounters[item]));
            if constexpr (std::is_void_v<Result>)
            {
              estimator.EstimatePoint(points[i].data(), request.Seed,
                static_cast<std::uint64_t>(first), count, recorders[item], blockCounters[item]);
            }
            else
            {
              // The status is the same for every block of a point.
              pointStatus[i] = estimator.EstimatePoint(points[i].data(), request.Seed,
                static_cast<std::uint64_t>(first), count, recorders[item], blockCounters[item]);
            }
            if constexpr (PointWalks::HasContinueBlock<Estimator>::value)
            {
              if (kept && first + count == walks)
              {
                lastHistory[i] = estimator.BlockHistory();
              }
            }
            blockDone[item] = 1;
            walksDone.fetch_add(static_cast<std::uint64_t>(count), std::memory_order_relaxed);
          }
          if (!estimator.SourceSupportIsBounded())
          {
            unbounded = true;
          }
        };
        if (derivativeWalks)
        {
          DerivativeWalkOnSpheres<DIM> estimator(
            *this->Shape, this->Walk, request.Derivatives, volume.get(), this->Concentrated());
          runBlocks(estimator);
        }
        else if (this->Mixed)
        {
          WalkOnStarsEstimator<DIM> estimator(
            *this->Mixed, this->Walk, volume.get(), this->Concentrated());
          runBlocks(estimator);
          backFaceHits.fetch_add(estimator.BackFaceHits(), std::memory_order_relaxed);
        }
        else
        {
          WalkOnSpheresEstimator<DIM> estimator(
            *this->Shape, this->Walk, volume.get(), this->Concentrated());
          runBlocks(estimator);
        }
      },
      report, 0.1, 1);

    RunningStatistics stats(sampleSize, this->SolutionComponents());
    const SampleLayout layout = this->Layout(request);
    WalkCounters sum;
    std::array<std::uint64_t, 3> counts = { 0, 0, 0 };
    std::uint64_t unreliable = 0;
    for (std::size_t i = 0; i < numPoints; ++i)
    {
      const std::size_t firstItem = i * blocksPerPoint;
      bool reached = true;
      for (std::size_t b = 0; b < blocksPerPoint; ++b)
      {
        reached = reached && blockDone[firstItem + b];
      }
      if (!reached)
      {
        continue; // aborted: the point never reaches the sink
      }
      WalkCounters counters;
      unsigned char keptStatus = 0;
      startPoint(i, stats, counters, keptStatus);
      const DerivativeStatus status =
        derivativeWalks ? pointStatus[i] : static_cast<DerivativeStatus>(keptStatus);
      for (std::size_t b = 0; b < blocksPerPoint; ++b)
      {
        recorders[firstItem + b].ReplayInto(stats);
        counters.Add(blockCounters[firstItem + b]);
      }
      if (kept)
      {
        kept->Save(i, stats, counters, static_cast<unsigned char>(status));
        if (derivativeWalks)
        {
          kept->SaveHistory(i, lastHistory[i]);
        }
      }
      sunk[i] = 1;
      if (derivativeWalks)
      {
        counts[static_cast<int>(status)] += 1;
      }
      sum.Add(counters);
      unreliable += this->ErrorBar(stats, counters, layout).Reliable ? 0 : 1;
      sink(i, stats, counters, status);
      finished.fetch_add(1, std::memory_order_relaxed);
    }
    addTotals(sum, counts, !unbounded.load(), unreliable);
    return completed;
  }

  // The boundary walks end on: the whole one, or a mixed one's Dirichlet
  // part (its Neumann part when it has none), which gives the values'
  // components; Mixed is set for walk on stars.
  std::shared_ptr<const Boundary<DIM>> Shape;
  std::shared_ptr<const MixedBoundary<DIM>> Mixed;
  WalkSettings Walk;
  std::shared_ptr<const SourceSet<DIM>> Sources;
  std::shared_ptr<const SourceDensityMap<DIM>> Density;
  bool ConstantData = false; // constant boundary values and no sources
};
} // namespace gridfree

#endif
