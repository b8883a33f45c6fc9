// How one batch's walks run on the threads (Problem::Estimate hands every
// batch to one of these). Two schedules give the same numbers bit for bit:
// * points over the threads (the usual one): each thread takes points and
//   runs each point's walks in order (PointWalks.h);
// * walks in blocks (few points, several threads): each point's walks are
//   cut into blocks spread over the threads, each block recorded and then
//   replayed in walk order, so the numbers are those of one thread.
// Either continues from running sums kept by the previous batch and keeps
// its own (RunningSumsCache.h), reports progress on the calling thread, and
// stops at an abort within one chunk of walks.
#ifndef GRIDFREE_PROBLEM_BATCH_SCHEDULER_H
#define GRIDFREE_PROBLEM_BATCH_SCHEDULER_H

#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/problem/Batch.h>
#include <gridfree/problem/PointWalks.h>
#include <gridfree/stars/StarDerivativeWalks.h>
#include <gridfree/stars/WalkOnStars.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/statistics/RunningSumsCache.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <mutex>
#include <type_traits>
#include <vector>

namespace gridfree
{
template <int DIM>
class Problem;

template <int DIM>
class BatchScheduler
{
public:
  // The batch of Problem::Estimate (see there); nothing runs until Run().
  BatchScheduler(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request, const PointSink& sink, const BatchProgressCallback& progress,
    RunningSumsCache* kept)
    : P(problem)
    , Points(points)
    , Request(request)
    , Sink(sink)
    , Progress(progress)
    , Kept(kept)
  {
  }

  BatchSummary Run()
  {
    BatchSummary& summary = this->Summary;
    this->DerivativeWalks = this->Request.DerivativeWalks();
    summary.Layout = this->P.Layout(this->Request);
    this->SampleSize = summary.Layout.Size;
    this->NumPoints = this->Points.size();
    this->Walks = std::max(0, this->Request.WalksPerPoint);
    RunningSumsCache* kept = this->Kept;

    // Progressive refinement: continue from the kept sums and keep this
    // batch's, with the derivative estimator's control-block history, so
    // that the next batch can continue from any walk count.
    this->BlockWalks =
      this->DerivativeWalks ? DerivativeWalkOnSpheres<DIM>::kControlBlock : 64;
    this->Target = this->Request.TargetStandardError;
    this->Resumed = kept &&
      kept->CanResume(this->NumPoints, this->SampleSize, this->DerivativeWalks, this->Target,
        static_cast<std::uint64_t>(this->Walks));
    if (kept && !this->Resumed)
    {
      kept->Reset(this->NumPoints, this->SampleSize, this->DerivativeWalks, this->Target,
        this->P.SolutionComponents());
    }
    // A tighter target than the kept sums': their stopped points are checked again.
    this->TighterTarget = this->Resumed && this->Target > 0.0 && this->Target < kept->KeptTarget();
    if (this->Resumed)
    {
      kept->Retarget(this->Target);
    }
    // Every point holds the same walks unless an abort (or a target) left
    // them uneven; each point continues from its own count.
    const bool uniformStart = !this->Resumed || kept->Uniform();
    this->StartWalks = this->Resumed ? static_cast<int>(kept->KeptWalks()) : 0;
    // After an abort, the walks every point resumed from.
    summary.ResumedWalksPerPoint = !this->Resumed ? 0
      : kept->Interrupted()                       ? static_cast<int>(kept->FewestWalks())
                                                  : this->StartWalks;

    this->ValueComponents = this->P.SolutionComponents();
    const int threadCount = ResolveThreadCount(this->Request.Threads);
    // Walk-level blocks follow the control blocks (multiples of BlockWalks);
    // a batch resumed inside one starts with the rest of that block.
    const int walks = this->Walks;
    const int startWalks = this->StartWalks;
    const int blockWalks = this->BlockWalks;
    this->LeadWalks =
      std::min((blockWalks - startWalks % blockWalks) % blockWalks, walks - startWalks);
    this->BlocksPerPoint = static_cast<std::size_t>(this->LeadWalks > 0) +
      static_cast<std::size_t>((walks - startWalks - this->LeadWalks + blockWalks - 1) / blockWalks);
    // Walking on where unreliable decides point by point: points over the threads.
    this->WalkOnMost = this->Target <= 0.0 && this->Request.WalkOnWhereUnreliable > 1
      ? static_cast<int>(std::min<long long>(
          static_cast<long long>(walks) * this->Request.WalkOnWhereUnreliable,
          std::numeric_limits<int>::max()))
      : walks;
    const bool walkLevel = this->Target <= 0.0 && this->WalkOnMost == walks && uniformStart &&
      threadCount > 1 &&
      this->NumPoints < 2 * static_cast<std::size_t>(threadCount) && this->BlocksPerPoint > 1 &&
      static_cast<double>(this->NumPoints) * (walks - startWalks) * this->SampleSize <=
        16.0 * 1024 * 1024;

    this->Start = std::chrono::steady_clock::now();
    this->TotalWalks = 0.0;
    if (uniformStart)
    {
      this->TotalWalks =
        static_cast<double>(this->NumPoints) * static_cast<double>(walks - startWalks);
    }
    else
    {
      for (std::size_t i = 0; i < this->NumPoints; ++i)
      {
        // A point that walked on holds more than this batch's count.
        this->TotalWalks +=
          std::max(0.0, static_cast<double>(walks) - static_cast<double>(kept->Walks(i)));
      }
    }

    // Points handed to the sink (an abort leaves some out; counted with or
    // without kept sums).
    this->Sunk.assign(this->NumPoints, 0);
    summary.Completed = walkLevel ? this->WalksInBlocks() : this->PointsOverThreads();
    if (kept && !summary.Completed)
    {
      this->SinkKeptPoints();
    }
    summary.PointsFinished = summary.Completed ? this->NumPoints : this->Finished.load();
    summary.PointsWithoutWalks = 0;
    for (std::size_t i = 0; i < this->Sunk.size() && !summary.Completed; ++i)
    {
      summary.PointsWithoutWalks += this->Sunk[i] ? 0 : 1;
    }
    summary.WalksRun = this->WalksDone.load();
    summary.BackFaceHits = this->BackFaceHits.load();
    summary.PointsWalkedOn = this->PointsWalkedOn.load();
    summary.WalksOnForReliability = this->WalksOn.load();
    summary.Seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - this->Start).count();
    if (kept)
    {
      if (summary.Completed && walks > 0)
      {
        // A target batch's points stop at different counts, and so do
        // points that walked on for a reliable error bar.
        kept->SetKeptWalks(static_cast<std::uint64_t>(walks),
          this->Target <= 0.0 && !this->AnyPointAboveCount.load());
      }
      else
      {
        kept->KeepWhatEachPointHolds();
      }
    }
    return summary;
  }

private:
  // A point's statistics before its walks: empty, or the kept ones.
  void StartPoint(
    std::size_t i, RunningStatistics& stats, WalkCounters& counters, unsigned char& status) const
  {
    stats.Reset();
    counters = WalkCounters();
    status = 0;
    if (this->Resumed)
    {
      this->Kept->Load(i, stats, counters, status);
    }
  }

  bool Report(double fraction)
  {
    if (!this->Progress)
    {
      return true;
    }
    BatchProgress p;
    p.WalksRun = this->WalksDone.load(std::memory_order_relaxed);
    p.WalksToRun = this->TotalWalks;
    p.Seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - this->Start).count();
    p.PointsFraction = fraction;
    p.Fraction = std::max(fraction,
      this->TotalWalks > 0.0 ? std::min(1.0, static_cast<double>(p.WalksRun) / this->TotalWalks)
                             : 1.0);
    return this->Progress(p);
  }

  void AddTotals(const WalkCounters& sum, const std::array<std::uint64_t, 3>& counts,
    bool bounded, std::uint64_t unreliable)
  {
    std::lock_guard<std::mutex> lock(this->TotalsMutex);
    this->Summary.Totals.Add(sum);
    this->Summary.UnreliableErrorBars += unreliable;
    for (int k = 0; k < 3; ++k)
    {
      this->Summary.StatusCounts[k] += counts[k];
    }
    this->Summary.UnboundedSource = this->Summary.UnboundedSource || !bounded;
  }

  // Runs `run` with this thread's estimator for the request (derivative
  // walks, walk on stars, or plain walks) and says whether the source's
  // support stayed bounded; walk on stars' back-face hits are added up.
  template <class RunWith>
  bool WithEstimator(RunWith&& run)
  {
    if (this->P.Coefficients)
    {
      VaryingCoefficientEstimator<DIM> estimator(*this->P.Shape, *this->P.Coefficients->Field,
        *this->P.Coefficients->Majorant, this->P.VaryingSettings(this->Request.Derivatives.Gradient));
      run(estimator);
      return true;
    }
    auto volume = this->P.MakeVolume();
    if (this->DerivativeWalks && this->P.Mixed)
    {
      StarDerivativeWalks<DIM> estimator(*this->P.Mixed, this->P.Walk, this->Request.Derivatives,
        volume.get(), this->P.Concentrated());
      run(estimator);
      this->BackFaceHits.fetch_add(
        estimator.Continuations().BackFaceHits(), std::memory_order_relaxed);
      return estimator.SourceSupportIsBounded();
    }
    if (this->DerivativeWalks)
    {
      DerivativeWalkOnSpheres<DIM> estimator(*this->P.Shape, this->P.Walk,
        this->Request.Derivatives, volume.get(), this->P.Concentrated());
      estimator.SetGuide(this->P.Guide.get());
      estimator.SetPeakGuide(this->P.Peak.get());
      run(estimator);
      return estimator.SourceSupportIsBounded();
    }
    if (this->P.Mixed)
    {
      WalkOnStarsEstimator<DIM> estimator(
        *this->P.Mixed, this->P.Walk, volume.get(), this->P.Concentrated());
      run(estimator);
      this->BackFaceHits.fetch_add(estimator.BackFaceHits(), std::memory_order_relaxed);
      return estimator.SourceSupportIsBounded();
    }
    WalkOnSpheresEstimator<DIM> estimator(
      *this->P.Shape, this->P.Walk, volume.get(), this->P.Concentrated());
    estimator.SetGuide(this->P.Guide.get());
    estimator.SetPeakGuide(this->P.Peak.get());
    run(estimator);
    return estimator.SourceSupportIsBounded();
  }

  // Points over the threads: each point's walks in order, a fixed count or
  // until the target, continuing from kept sums and keeping them.
  bool PointsOverThreads()
  {
    const std::vector<std::array<double, 3>>& points = this->Points;
    RunningSumsCache* kept = this->Kept;
    const bool resumed = this->Resumed;
    const double target = this->Target;
    const int walks = this->Walks;
    const std::uint64_t seed = this->Request.Seed;
    const int valueComponents = this->ValueComponents;
    const SampleLayout& layout = this->Summary.Layout;
    const bool spreadPossible = !this->P.ConstantData;
    return ParallelForWithProgress(
      this->NumPoints, this->Request.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
        WalkCounters sum;
        std::array<std::uint64_t, 3> counts = { 0, 0, 0 };
        std::uint64_t unreliable = 0;
        auto runPoints = [&](auto& estimator) {
          RunningStatistics stats(this->SampleSize, valueComponents);
          for (std::size_t i = begin; i < end && !cancel.load(std::memory_order_relaxed); ++i)
          {
            WalkCounters counters;
            unsigned char keptStatus = 0;
            this->StartPoint(i, stats, counters, keptStatus);
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
              if (stopped && this->TighterTarget)
              {
                // Stopped at a looser target: it stays stopped only if it
                // meets this one where it stands.
                stopped = PointWalks::MeetsTarget(stats, counters, target, valueComponents,
                  layout.Weight, spreadPossible, status, &this->P.ErrorRule(counters));
              }
              // The point's own count: kept sums differ after an abort.
              const int from = static_cast<int>(stats.SampleCount());
              bool ran = true;
              if (target > 0.0)
              {
                ran = stopped ||
                  PointWalks::EstimateToTarget(estimator, points[i].data(), seed, from, walks,
                    target, valueComponents, layout.Weight, spreadPossible, stats, counters,
                    cancel, this->WalksDone, status, stopped,
                    [&](const WalkCounters& c) -> const ErrorBarRule& {
                      return this->P.ErrorRule(c);
                    });
              }
              else
              {
                ran = PointWalks::EstimateInChunks(estimator, points[i].data(), seed, from,
                  walks, stats, counters, cancel, this->WalksDone, status, from > 0);
                if (ran && this->WalkOnMost > walks)
                {
                  const std::uint64_t before = stats.SampleCount();
                  ran = PointWalks::WalkOnUntilReliable(estimator, points[i].data(), seed,
                    walks, this->WalkOnMost, stats, counters, cancel, this->WalksDone, status,
                    [&](const RunningStatistics& s, const WalkCounters& c, DerivativeStatus d) {
                      // Uneven screening weights stay uneven however many
                      // walks run (ErrorBarReliability.h); only the bound of
                      // the walk values, a shift D/(s√N) that falls as
                      // 1/√N, can clear them. No walking on where it would
                      // still be too large at the most walks.
                      const ErrorBarCheck check = this->P.ErrorBar(s, c, layout, d);
                      const double fall = std::sqrt(
                        static_cast<double>(s.SampleCount()) / this->WalkOnMost);
                      return check.Reliable ||
                        (check.UnevenWeights &&
                          !(check.UnseenWalkShift * fall <= this->P.ErrorRule(c).MaxUnseenShift));
                    });
                  if (stats.SampleCount() > before)
                  {
                    this->PointsWalkedOn.fetch_add(1, std::memory_order_relaxed);
                    this->WalksOn.fetch_add(stats.SampleCount() - before, std::memory_order_relaxed);
                  }
                }
                if (stats.SampleCount() > static_cast<std::uint64_t>(walks))
                {
                  this->AnyPointAboveCount.store(true, std::memory_order_relaxed);
                }
              }
              // Kept also when cut short: the next batch continues from the
              // walks it ran (whole chunks, with their history).
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
            this->Finished.fetch_add(ran ? 1 : 0, std::memory_order_relaxed);
            if (this->DerivativeWalks)
            {
              counts[static_cast<int>(status)] += 1;
            }
            sum.Add(counters);
            unreliable += this->P.ErrorBar(stats, counters, layout, status).Reliable ? 0 : 1;
            this->Sink(i, stats, counters, status);
            this->Sunk[i] = 1;
            if (!ran)
            {
              return; // aborted: the points after this one are not reached
            }
          }
        };
        const bool bounded = this->WithEstimator(runPoints);
        this->AddTotals(sum, counts, bounded, unreliable);
      },
      [this](double fraction) { return this->Report(fraction); });
  }

  // Walks in blocks: few points, several threads. Each point's walks in
  // blocks spread over the threads, each block recorded and then replayed
  // in walk order, so the numbers are bit for bit those of one thread.
  // Blocks of the derivative estimator are its control blocks, whose
  // control variates only use the walks before them in the same block: a
  // batch resumed inside a block starts with its remaining LeadWalks walks,
  // continuing from the kept history, and keeps the history of each
  // point's last block.
  bool WalksInBlocks()
  {
    const std::vector<std::array<double, 3>>& points = this->Points;
    const BatchRequest& request = this->Request;
    RunningSumsCache* kept = this->Kept;
    const bool derivativeWalks = this->DerivativeWalks;
    const int walks = this->Walks;
    const int startWalks = this->StartWalks;
    const int leadWalks = this->LeadWalks;
    const int blockWalks = this->BlockWalks;
    const std::size_t blocksPerPoint = this->BlocksPerPoint;
    const int sampleSize = this->SampleSize;
    const std::size_t numPoints = this->NumPoints;
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
            this->WalksDone.fetch_add(static_cast<std::uint64_t>(count), std::memory_order_relaxed);
          }
        };
        if (!this->WithEstimator(runBlocks))
        {
          unbounded = true;
        }
      },
      [this](double fraction) { return this->Report(fraction); }, 0.1, 1);

    RunningStatistics stats(sampleSize, this->P.SolutionComponents());
    const SampleLayout& layout = this->Summary.Layout;
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
      this->StartPoint(i, stats, counters, keptStatus);
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
      this->Sunk[i] = 1;
      if (derivativeWalks)
      {
        counts[static_cast<int>(status)] += 1;
      }
      sum.Add(counters);
      unreliable += this->P.ErrorBar(stats, counters, layout, status).Reliable ? 0 : 1;
      this->Sink(i, stats, counters, status);
      this->Finished.fetch_add(1, std::memory_order_relaxed);
    }
    this->AddTotals(sum, counts, !unbounded.load(), unreliable);
    return completed;
  }

  // After an abort with kept sums: the points the abort left out, with the
  // walks kept for them.
  void SinkKeptPoints()
  {
    RunningStatistics stats(this->SampleSize, this->ValueComponents);
    WalkCounters sum;
    std::array<std::uint64_t, 3> counts = { 0, 0, 0 };
    std::uint64_t unreliable = 0;
    for (std::size_t i = 0; i < this->NumPoints; ++i)
    {
      if (this->Sunk[i])
      {
        continue;
      }
      WalkCounters counters;
      unsigned char status = 0;
      this->StartPoint(i, stats, counters, status);
      if (stats.SampleCount() == 0)
      {
        continue;
      }
      if (this->DerivativeWalks)
      {
        counts[status] += 1;
      }
      sum.Add(counters);
      unreliable += this->P
                      .ErrorBar(stats, counters, this->Summary.Layout,
                        static_cast<DerivativeStatus>(status))
                      .Reliable
        ? 0
        : 1;
      this->Sink(i, stats, counters, static_cast<DerivativeStatus>(status));
      this->Sunk[i] = 1;
    }
    this->AddTotals(sum, counts, true, unreliable);
  }

  const Problem<DIM>& P;
  const std::vector<std::array<double, 3>>& Points;
  const BatchRequest& Request;
  const PointSink& Sink;
  const BatchProgressCallback& Progress;
  RunningSumsCache* Kept;

  BatchSummary Summary;
  bool DerivativeWalks = false;
  int SampleSize = 0;
  std::size_t NumPoints = 0;
  int Walks = 0;
  int BlockWalks = 64;
  double Target = 0.0;
  bool Resumed = false;
  bool TighterTarget = false;
  int StartWalks = 0;
  int LeadWalks = 0;
  std::size_t BlocksPerPoint = 0;
  int ValueComponents = 1;
  std::chrono::steady_clock::time_point Start;
  double TotalWalks = 0.0;
  std::atomic<std::uint64_t> WalksDone{ 0 };
  std::atomic<std::uint64_t> BackFaceHits{ 0 };
  // Fixed-count mode: the most walks a point may walk on to (Walks when it
  // does not walk on), the points that did and their added walks, and
  // whether any point holds more than Walks (also from earlier batches).
  int WalkOnMost = 0;
  std::atomic<std::uint64_t> PointsWalkedOn{ 0 };
  std::atomic<std::uint64_t> WalksOn{ 0 };
  std::atomic<bool> AnyPointAboveCount{ false };
  std::mutex TotalsMutex;
  std::vector<unsigned char> Sunk;
  std::atomic<std::uint64_t> Finished{ 0 };
};
} // namespace gridfree

#endif
