// Running mean and variance (Welford's update) for a fixed number of
// components, so a multi-component boundary array is estimated from the same
// walks and each component gets its own variance.
#ifndef GRIDFREE_STATISTICS_RUNNING_STATISTICS_H
#define GRIDFREE_STATISTICS_RUNNING_STATISTICS_H

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace gridfree
{
class RunningStatistics
{
public:
  explicit RunningStatistics(int components = 1)
    : Mean(components, 0.0)
    , M2(components, 0.0)
  {
  }

  void Reset()
  {
    this->Count = 0;
    std::fill(this->Mean.begin(), this->Mean.end(), 0.0);
    std::fill(this->M2.begin(), this->M2.end(), 0.0);
  }

  // Adds one sample with Components() values. Welford's form stays accurate
  // when the mean is large compared with the spread (e.g. temperatures in K).
  void Add(const double* sample)
  {
    ++this->Count;
    const double invCount = 1.0 / static_cast<double>(this->Count);
    for (std::size_t c = 0; c < this->Mean.size(); ++c)
    {
      const double delta = sample[c] - this->Mean[c];
      this->Mean[c] += delta * invCount;
      this->M2[c] += delta * (sample[c] - this->Mean[c]);
    }
  }

  int Components() const { return static_cast<int>(this->Mean.size()); }
  std::size_t SampleCount() const { return this->Count; }

  // The exact state (count, means and sums of squared deviations), to be
  // kept and restored later: adding more samples to a restored state gives
  // bit for bit what adding all of them in one go would.
  void SaveState(std::size_t& count, double* mean, double* m2) const
  {
    count = this->Count;
    std::copy(this->Mean.begin(), this->Mean.end(), mean);
    std::copy(this->M2.begin(), this->M2.end(), m2);
  }
  void RestoreState(std::size_t count, const double* mean, const double* m2)
  {
    this->Count = count;
    std::copy(mean, mean + this->Mean.size(), this->Mean.begin());
    std::copy(m2, m2 + this->M2.size(), this->M2.begin());
  }
  double GetMean(int c) const { return this->Mean[c]; }

  // Unbiased sample variance of one sample, s^2 (N - 1 in the denominator).
  double SampleVariance(int c) const
  {
    if (this->Count < 2)
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    return this->M2[c] / static_cast<double>(this->Count - 1);
  }

  // Variance of the reported mean, s^2 / N: what the *_Variance arrays hold.
  double VarianceOfMean(int c) const
  {
    return this->SampleVariance(c) / static_cast<double>(this->Count);
  }

private:
  std::size_t Count = 0;
  std::vector<double> Mean;
  std::vector<double> M2;
};

// Keeps samples in the order they are added, to be added to a
// RunningStatistics later. Walks of one point can then run on several
// threads, each block of walks into its own recorder, and be replayed in walk
// order: the result is bit for bit what one thread adding them in order
// gives, whatever the number of threads (Welford's update is not
// associative, so merging partial statistics would not be).
class SampleRecorder
{
public:
  explicit SampleRecorder(int components = 1)
    : NumberOfComponents(components)
  {
  }

  void Clear() { this->Values.clear(); }
  void Reserve(std::size_t samples) { this->Values.reserve(samples * this->NumberOfComponents); }
  void Add(const double* sample)
  {
    this->Values.insert(this->Values.end(), sample, sample + this->NumberOfComponents);
  }
  std::size_t SampleCount() const { return this->Values.size() / this->NumberOfComponents; }

  void ReplayInto(RunningStatistics& stats) const
  {
    for (std::size_t i = 0; i < this->Values.size(); i += this->NumberOfComponents)
    {
      stats.Add(this->Values.data() + i);
    }
  }

private:
  std::size_t NumberOfComponents;
  std::vector<double> Values;
};
} // namespace gridfree

#endif
