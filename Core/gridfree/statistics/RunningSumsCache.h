// The running sums of every probe point's walks, kept between solves for
// progressive refinement (paper Sec. 5.2): a solve with more walks per point
// continues from them and runs only the walks that are missing.
//
// Every walk's random stream depends only on the seed, the point and the
// walk's number, and the sums are Welford states restored exactly, so the
// continued result is bit for bit that of one solve with all the walks. The
// derivative estimator's control variates also use the running means of the
// walks before them in the same control block (256 walks), so for it the
// cache keeps that block's running state too ("history"): a solve can then
// continue from any walk count, inside a block as well.
//
// An aborted solve keeps what it ran too: each point holds its own walk
// count then (those finished, those cut short between chunks, those not
// reached with what an earlier solve kept), and the next solve continues
// every point from its own count, with the same result as one solve.
#ifndef GRIDFREE_STATISTICS_RUNNING_SUMS_CACHE_H
#define GRIDFREE_STATISTICS_RUNNING_SUMS_CACHE_H

#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gridfree
{
class RunningSumsCache
{
public:
  /// Empties the cache and sizes it for `points` points of `components`
  /// numbers per walk, with a control-block history of `components` numbers
  /// per point when `history` is set (the derivative estimator), for a batch
  /// of target standard error `target` (0: a fixed count of walks). The
  /// first `tailComponents` numbers of each walk keep higher sums too
  /// (RunningStatistics).
  void Reset(std::size_t points, int components, bool history, double target = 0.0,
    int tailComponents = 0)
  {
    this->NumberOfPoints = points;
    this->NumberOfComponents = components;
    this->KeepsHistory = history;
    this->Target = target;
    this->Kept = 0;
    this->AllKept = true;
    this->WasInterrupted = false;
    this->Sums.Assign(points, components, tailComponents);
    this->History.Assign(history ? points : 0, components, 0);
    this->Counters.assign(points, WalkCounters());
    this->Statuses.assign(points, 0);
    this->StoppedAtTarget.assign(target > 0.0 ? points : 0, 0);
  }

  /// Frees the memory; nothing can be resumed afterwards.
  void Clear()
  {
    *this = RunningSumsCache();
  }

  /// Whether a solve of `points` points with `components` numbers per walk
  /// (and a history or not), target `target` and `walks` walks per point (at
  /// most, with a target) can continue from the kept sums, with the result
  /// of one solve of those settings:
  /// - the same target (or none), no fewer walks than any point holds;
  /// - a fixed count of walks after a target (points that stopped at the
  ///   target run on to the count, as its walks are those of a fixed count);
  /// - a tighter target after a looser one (a point stopped at the looser
  ///   one is checked again; it could not have stopped earlier at the
  ///   tighter one). A looser target cannot continue: a solve with it would
  ///   have stopped some points before the walks they hold.
  bool CanResume(std::size_t points, int components, bool history, double target,
    std::uint64_t walks) const
  {
    const bool targetFits = target == this->Target || target <= 0.0 ||
      (this->Target > 0.0 && target < this->Target);
    return this->Kept > 0 && points == this->NumberOfPoints &&
      components == this->NumberOfComponents && history == this->KeepsHistory && targetFits &&
      walks >= this->Kept;
  }

  /// The target the kept sums were computed for (0: a fixed count).
  double KeptTarget() const { return this->Target; }

  /// Continues the kept sums under `target` (CanResume said it fits):
  /// stopped points stay marked as such for a tighter target, which checks
  /// them again.
  void Retarget(double target)
  {
    if (target == this->Target)
    {
      return;
    }
    this->Target = target;
    if (target <= 0.0)
    {
      this->StoppedAtTarget.clear();
    }
    else if (this->StoppedAtTarget.empty())
    {
      this->StoppedAtTarget.assign(this->NumberOfPoints, 0);
    }
  }

  /// The most walks any point holds (0: none): a solve continues only with
  /// at least as many walks per point.
  std::uint64_t KeptWalks() const { return this->Kept; }

  /// Whether every point holds KeptWalks() walks (false after an abort, or
  /// after a target batch, whose points stop at different counts).
  bool Uniform() const { return this->AllKept; }

  /// Whether the kept sums are those of an aborted solve.
  bool Interrupted() const { return this->WasInterrupted; }

  /// The fewest walks any point holds.
  std::uint64_t FewestWalks() const
  {
    std::uint64_t fewest = this->Kept;
    for (std::size_t count : this->Sums.Counts)
    {
      fewest = std::min<std::uint64_t>(fewest, count);
    }
    return fewest;
  }

  /// The walks point i holds.
  std::uint64_t Walks(std::size_t i) const { return this->Sums.Counts[i]; }

  /// Restores point i's kept state (all zero when nothing is kept).
  void Load(std::size_t i, RunningStatistics& stats, WalkCounters& counters,
    unsigned char& status) const
  {
    this->Sums.Load(i, stats);
    counters = this->Counters[i];
    status = this->Statuses[i];
  }

  /// Keeps point i's state; `stopped`: its walks stopped at the target.
  void Save(std::size_t i, const RunningStatistics& stats, const WalkCounters& counters,
    unsigned char status, bool stopped = false)
  {
    this->Sums.Save(i, stats);
    this->Counters[i] = counters;
    this->Statuses[i] = status;
    if (!this->StoppedAtTarget.empty())
    {
      this->StoppedAtTarget[i] = stopped ? 1 : 0;
    }
  }

  /// Whether point i's kept walks stopped at the target (a target batch).
  bool Stopped(std::size_t i) const
  {
    return !this->StoppedAtTarget.empty() && this->StoppedAtTarget[i] != 0;
  }

  /// Restores / keeps point i's control-block history (a cache reset with
  /// `history`).
  void LoadHistory(std::size_t i, RunningStatistics& history) const
  {
    this->History.Load(i, history);
  }
  void SaveHistory(std::size_t i, const RunningStatistics& history)
  {
    this->History.Save(i, history);
  }

  /// Marks every point's state as holding `walks` walks (after a complete
  /// solve of a fixed count; a target solve's points hold at most `walks`).
  void SetKeptWalks(std::uint64_t walks, bool uniform = true)
  {
    this->Kept = walks;
    this->AllKept = uniform;
    this->WasInterrupted = false;
  }

  /// After an aborted solve: every point holds the walks it was saved with
  /// (or was loaded with), which differ from point to point.
  void KeepWhatEachPointHolds()
  {
    std::uint64_t most = 0;
    bool uniform = true;
    for (std::size_t count : this->Sums.Counts)
    {
      uniform = uniform && count == this->Sums.Counts[0];
      most = std::max<std::uint64_t>(most, count);
    }
    this->Kept = most;
    this->AllKept = uniform && this->StoppedAtTarget.empty();
    this->WasInterrupted = true;
  }

  /// Bytes held.
  std::size_t MemoryBytes() const
  {
    return this->Sums.MemoryBytes() + this->History.MemoryBytes() +
      this->Counters.capacity() * sizeof(WalkCounters) + this->Statuses.capacity() +
      this->StoppedAtTarget.capacity();
  }

private:
  // Welford states (count, means, M2s, and the M3s and M4s of the first
  // TailComponents) of `points` statistics.
  struct States
  {
    void Assign(std::size_t points, int components, int tailComponents)
    {
      this->Components = static_cast<std::size_t>(components);
      this->TailComponents =
        static_cast<std::size_t>(std::max(0, std::min(tailComponents, components)));
      this->Counts.assign(points, 0);
      this->Means.assign(points * this->Components, 0.0);
      this->M2s.assign(points * this->Components, 0.0);
      this->M3s.assign(points * this->TailComponents, 0.0);
      this->M4s.assign(points * this->TailComponents, 0.0);
    }
    void Load(std::size_t i, RunningStatistics& stats) const
    {
      const std::size_t at = i * this->Components;
      const std::size_t tail = i * this->TailComponents;
      stats.RestoreState(this->Counts[i], &this->Means[at], &this->M2s[at],
        this->M3s.data() + tail, this->M4s.data() + tail);
    }
    void Save(std::size_t i, const RunningStatistics& stats)
    {
      const std::size_t at = i * this->Components;
      const std::size_t tail = i * this->TailComponents;
      stats.SaveState(this->Counts[i], &this->Means[at], &this->M2s[at],
        this->M3s.data() + tail, this->M4s.data() + tail);
    }
    std::size_t MemoryBytes() const
    {
      return this->Counts.capacity() * sizeof(std::size_t) +
        (this->Means.capacity() + this->M2s.capacity() + this->M3s.capacity() +
          this->M4s.capacity()) *
        sizeof(double);
    }
    std::size_t Components = 0;
    std::size_t TailComponents = 0;
    std::vector<std::size_t> Counts;
    std::vector<double> Means;
    std::vector<double> M2s;
    std::vector<double> M3s;
    std::vector<double> M4s;
  };

  std::size_t NumberOfPoints = 0;
  int NumberOfComponents = 0;
  bool KeepsHistory = false;
  double Target = 0.0;
  std::uint64_t Kept = 0;
  bool AllKept = true;
  bool WasInterrupted = false;
  States Sums;
  States History;
  std::vector<WalkCounters> Counters;
  std::vector<unsigned char> Statuses;
  std::vector<unsigned char> StoppedAtTarget;
};
} // namespace gridfree

#endif
