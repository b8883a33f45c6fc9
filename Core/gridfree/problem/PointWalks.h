// How one point's walks run inside a batch (BatchScheduler.h's schedulers run
// every point through these): in chunks with a check for abort between
// them, and in target-error mode until the standard error of the point's
// value is reached with a reliable error bar. The walks are always those of
// a fixed-count run, in the same order, so stopping early or continuing
// later gives the numbers of one run.
#ifndef GRIDFREE_PROBLEM_POINT_WALKS_H
#define GRIDFREE_PROBLEM_POINT_WALKS_H

#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/statistics/ErrorBarReliability.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>

namespace gridfree
{
struct PointWalks
{
  // Walks of one point run in chunks of this many, with a check for abort
  // in between: a point with millions of walks must not make abort wait for
  // it. A multiple of the derivative estimator's control blocks (256), so
  // chunks give the same numbers as one call.
  static constexpr int kChunkWalks = 1024;
  // Target-error mode: walks before the first check, and between checks. The
  // first check waits for 128 walks: a point that stops on a lucky small
  // spread reports too small an error, and near the boundary, where walk
  // values are skewed (most walks end at once, a few travel far), 64 walks
  // gave |z| up to 5.5 on the test's probe, 128 at most 4.3 (the same as a
  // fixed count of walks there).
  static constexpr int kTargetFirstWalks = 128;
  static constexpr int kTargetCheckWalks = 32;

  // Runs walks number `from` to `to` - 1 of one point into stats/counters in
  // chunks of kChunkWalks, adding each finished chunk to `done` and stopping
  // between chunks when `cancel` is set. Returns false if they were not all
  // run; `status` receives the derivative estimator's status (unchanged for
  // the plain one). With `continuing`, the derivative estimator continues
  // the control block its history holds (walks up to `from` of this point).
  template <class Estimator>
  static bool EstimateInChunks(Estimator& estimator, const double xyz[3], std::uint64_t seed,
    int from, int to, RunningStatistics& stats, WalkCounters& counters,
    const std::atomic<bool>& cancel, std::atomic<std::uint64_t>& done, DerivativeStatus& status,
    bool continuing = false)
  {
    for (int first = from; first < to; first += kChunkWalks)
    {
      if constexpr (HasContinueBlock<Estimator>::value)
      {
        // The derivative estimator keeps its control history across calls
        // that continue the same point's walks (chunks, target-error legs).
        estimator.ContinueBlock(continuing || first > from);
      }
      if (first > from && cancel.load(std::memory_order_relaxed))
      {
        return false;
      }
      const int count = std::min(kChunkWalks, to - first);
      using Result = decltype(estimator.EstimatePoint(
        xyz, seed, std::uint64_t(0), count, stats, counters));
      if constexpr (std::is_void_v<Result>)
      {
        estimator.EstimatePoint(xyz, seed, static_cast<std::uint64_t>(first), count, stats, counters);
      }
      else
      {
        status = estimator.EstimatePoint(
          xyz, seed, static_cast<std::uint64_t>(first), count, stats, counters);
      }
      done.fetch_add(static_cast<std::uint64_t>(count), std::memory_order_relaxed);
    }
    return true;
  }

  // Target-error mode: walks `from`, from + 1, ... of one point until the
  // standard error of its value is at most `target` (checked after
  // kTargetFirstWalks walks, then every kTargetCheckWalks) or `most` walks
  // have run. The walks are those of a fixed-count run, in the same order:
  // stopping early only drops the later ones. `stopped` says whether a check
  // found the target reached; a point cut short by `most` between two
  // checks is not stopped, so that a later batch with a larger maximum
  // continues it to its next check, as a batch with that maximum from the
  // start would. A check also requires a reliable error bar
  // (ErrorBarReliability.h; weightSlot: the screened walk's weight, or −1).
  // Returns false when aborted.
  template <class Estimator>
  static bool EstimateToTarget(Estimator& estimator, const double xyz[3], std::uint64_t seed,
    int from, int most, double target, int valueComponents, int weightSlot,
    bool dataVary, RunningStatistics& stats,
    WalkCounters& counters, const std::atomic<bool>& cancel, std::atomic<std::uint64_t>& done,
    DerivativeStatus& status, bool& stopped,
    const std::function<const ErrorBarRule&(const WalkCounters&)>& rule = nullptr)
  {
    stopped = false;
    int walked = from;
    while (walked < most)
    {
      const int check = walked < kTargetFirstWalks
        ? kTargetFirstWalks
        : kTargetFirstWalks +
          ((walked - kTargetFirstWalks) / kTargetCheckWalks + 1) * kTargetCheckWalks;
      const int to = std::min(check, most);
      if (!EstimateInChunks(estimator, xyz, seed, walked, to, stats, counters, cancel, done,
            status, walked > 0))
      {
        return false;
      }
      walked = to;
      if (walked < check)
      {
        break; // the maximum came first: no check here
      }
      if (MeetsTarget(stats, counters, target, valueComponents, weightSlot, dataVary, status,
            rule ? &rule(counters) : nullptr))
      {
        stopped = true;
        break;
      }
    }
    return true;
  }

  // Fixed-count mode's walking on (BatchRequest::WalkOnWhereUnreliable):
  // from the walks the point holds, on to the next of the checks at
  // `walks` times 2, 4, 8, ... (and `most`), until `settled` says walking
  // on can stop (the error bar is reliable, or unreliable for a reason more
  // walks do not remove), or it holds `most`. Doubling keeps refinement
  // exact: a batch of twice the walks checks at counts the batch before
  // also checked, so a point that walked on past it was found unreliable
  // there, as one batch would have found it. (Few checks also keep the
  // bias of stopping at the first reliable look small.) Returns false when
  // aborted.
  template <class Estimator>
  static bool WalkOnUntilReliable(Estimator& estimator, const double xyz[3], std::uint64_t seed,
    int walks, int most, RunningStatistics& stats, WalkCounters& counters,
    const std::atomic<bool>& cancel, std::atomic<std::uint64_t>& done, DerivativeStatus& status,
    const std::function<bool(const RunningStatistics&, const WalkCounters&, DerivativeStatus)>&
      settled)
  {
    int walked = static_cast<int>(stats.SampleCount());
    while (walks > 0 && walked < most && !settled(stats, counters, status))
    {
      long long next = walks;
      while (next <= walked)
      {
        next *= 2;
      }
      const int to = static_cast<int>(std::min<long long>(most, next));
      if (!EstimateInChunks(
            estimator, xyz, seed, walked, to, stats, counters, cancel, done, status, true))
      {
        return false;
      }
      walked = to;
    }
    return true;
  }

  // Whether a point's walks so far reach the target standard error with a
  // reliable error bar: where EstimateToTarget stops a point.
  // (A point closer than ε, DerivativeStatus::OneSided, has an exact value:
  // see Problem::SpreadPossible.)
  static bool MeetsTarget(const RunningStatistics& stats, const WalkCounters& counters,
    double target, int valueComponents, int weightSlot, bool dataVary,
    DerivativeStatus status = DerivativeStatus::Interior, const ErrorBarRule* rule = nullptr)
  {
    const double targetVariance = target * target;
    bool reached = true;
    for (int c = 0; c < valueComponents && reached; ++c)
    {
      // NaN (a component that cannot be estimated) never reaches it.
      reached = stats.VarianceOfMean(c) <= targetVariance;
    }
    return reached &&
      CheckErrorBar(stats, 0, valueComponents, weightSlot,
        dataVary && counters.Steps > 0 && status != DerivativeStatus::OneSided,
        rule ? *rule : ErrorBarRule(), counters.ValueControlReach, counters.WeightReachOrOne())
        .Reliable;
  }

  template <class Estimator, class = void>
  struct HasContinueBlock : std::false_type
  {
  };
  template <class Estimator>
  struct HasContinueBlock<Estimator,
    std::void_t<decltype(std::declval<Estimator&>().ContinueBlock(true))>> : std::true_type
  {
  };
};
} // namespace gridfree

#endif
