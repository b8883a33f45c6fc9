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
  /// most, with a target) can continue from the kept sums.
  bool CanResume(std::size_t points, int components, bool history, double target,
    std::uint64_t walks) const
  {
    return this->Kept > 0 && points == this->NumberOfPoints &&
      components == this->NumberOfComponents && history == this->KeepsHistory &&
      target == this->Target && walks >= this->Kept;
  }

  /// Walks per point the kept sums hold (0: none).
  std::uint64_t KeptWalks() const { return this->Kept; }

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
  /// solve; an aborted one must Clear instead).
  void SetKeptWalks(std::uint64_t walks) { this->Kept = walks; }

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
  States Sums;
  States History;
  std::vector<WalkCounters> Counters;
  std::vector<unsigned char> Statuses;
  std::vector<unsigned char> StoppedAtTarget;
};
} // namespace gridfree

#endif
