// What a long preparation before the walks (smoothing a coefficient image,
// sampling a bound grid) shares with the thread that waits for it: the
// work done so far, for a progress bar, and whether to stop, for an Abort
// button. The preparation's parallel loops skip their remaining blocks once
// Stop is set and then throw PreparationStopped, so a stopped preparation
// leaves nothing half made behind.
#ifndef GRIDFREE_EXECUTION_PREPARATION_MONITOR_H
#define GRIDFREE_EXECUTION_PREPARATION_MONITOR_H

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <stdexcept>

namespace gridfree
{
class PreparationStopped : public std::runtime_error
{
public:
  PreparationStopped()
    : std::runtime_error("the preparation was stopped")
  {
  }
};

struct PreparationMonitor
{
  std::atomic<bool> Stop{ false };
  // Units of work (voxels smoothed, lattice points sampled): each stage
  // adds what it expects when it starts, so the fraction can step back
  // when a new stage begins; callers show the largest seen.
  std::atomic<std::uint64_t> Done{ 0 };
  std::atomic<std::uint64_t> Total{ 0 };

  bool Stopping() const { return this->Stop.load(std::memory_order_relaxed); }
  void Expect(std::uint64_t units) { this->Total.fetch_add(units, std::memory_order_relaxed); }
  void Finished(std::uint64_t units) { this->Done.fetch_add(units, std::memory_order_relaxed); }
  double Fraction() const
  {
    const std::uint64_t total = this->Total.load(std::memory_order_relaxed);
    return total ? std::min(1.0,
                     static_cast<double>(this->Done.load(std::memory_order_relaxed)) /
                       static_cast<double>(total))
                 : 0.0;
  }
};

// Throws PreparationStopped when `monitor` (may be null) asks to stop.
inline void ThrowIfStopped(const PreparationMonitor* monitor)
{
  if (monitor && monitor->Stopping())
  {
    throw PreparationStopped();
  }
}
} // namespace gridfree

#endif
