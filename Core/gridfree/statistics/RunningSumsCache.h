// The running sums of every probe point's walks, kept between solves for
// progressive refinement (paper Sec. 5.2): a solve with more walks per point
// continues from them and runs only the walks that are missing.
//
// Every walk's random stream depends only on the seed, the point and the
// walk's number, and the sums are Welford states restored exactly, so the
// continued result is bit for bit that of one solve with all the walks. One
// subtlety: the derivative estimator's control variates use the running means
// of the walks before them in the same block of `Block` walks (256), so the
// state is kept at the last block boundary, and the walks of a partial last
// block are run again when the solve continues.
#ifndef GRIDFREE_STATISTICS_RUNNING_SUMS_CACHE_H
#define GRIDFREE_STATISTICS_RUNNING_SUMS_CACHE_H

#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gridfree
{
class RunningSumsCache
{
public:
  /// Empties the cache and sizes it for `points` points of `components`
  /// numbers per walk, resumable at multiples of `block` walks.
  void Reset(std::size_t points, int components, int block)
  {
    this->NumberOfPoints = points;
    this->NumberOfComponents = components;
    this->BlockWalks = block > 0 ? block : 1;
    this->Kept = 0;
    this->Counts.assign(points, 0);
    this->Means.assign(points * components, 0.0);
    this->M2s.assign(points * components, 0.0);
    this->Counters.assign(points, WalkCounters());
    this->Statuses.assign(points, 0);
  }

  /// Frees the memory; nothing can be resumed afterwards.
  void Clear()
  {
    *this = RunningSumsCache();
  }

  /// Whether a solve of `points` points with `components` numbers per walk
  /// and `walks` walks per point can continue from the kept sums.
  bool CanResume(std::size_t points, int components, int block, std::uint64_t walks) const
  {
    return this->Kept > 0 && points == this->NumberOfPoints &&
      components == this->NumberOfComponents && block == this->BlockWalks && walks >= this->Kept;
  }

  /// Walks per point the kept sums hold (0: none).
  std::uint64_t KeptWalks() const { return this->Kept; }

  /// The walk count at which a solve of `walks` walks keeps its sums: the
  /// last block boundary at or below it.
  std::uint64_t ResumePoint(std::uint64_t walks) const
  {
    return walks / static_cast<std::uint64_t>(this->BlockWalks) *
      static_cast<std::uint64_t>(this->BlockWalks);
  }

  /// Restores point i's kept state (all zero when nothing is kept).
  void Load(std::size_t i, RunningStatistics& stats, WalkCounters& counters,
    unsigned char& status) const
  {
    const std::size_t at = i * static_cast<std::size_t>(this->NumberOfComponents);
    stats.RestoreState(this->Counts[i], &this->Means[at], &this->M2s[at]);
    counters = this->Counters[i];
    status = this->Statuses[i];
  }

  /// Keeps point i's state after ResumePoint(walks) walks.
  void Save(std::size_t i, const RunningStatistics& stats, const WalkCounters& counters,
    unsigned char status)
  {
    const std::size_t at = i * static_cast<std::size_t>(this->NumberOfComponents);
    stats.SaveState(this->Counts[i], &this->Means[at], &this->M2s[at]);
    this->Counters[i] = counters;
    this->Statuses[i] = status;
  }

  /// Marks every point's state as holding `walks` walks (after a complete
  /// solve; an aborted one must Clear instead).
  void SetKeptWalks(std::uint64_t walks) { this->Kept = walks; }

  /// Bytes held.
  std::size_t MemoryBytes() const
  {
    return this->Counts.capacity() * sizeof(std::size_t) +
      (this->Means.capacity() + this->M2s.capacity()) * sizeof(double) +
      this->Counters.capacity() * sizeof(WalkCounters) + this->Statuses.capacity();
  }

private:
  std::size_t NumberOfPoints = 0;
  int NumberOfComponents = 0;
  int BlockWalks = 1;
  std::uint64_t Kept = 0;
  std::vector<std::size_t> Counts;
  std::vector<double> Means;
  std::vector<double> M2s;
  std::vector<WalkCounters> Counters;
  std::vector<unsigned char> Statuses;
};
} // namespace gridfree

#endif
