// Running mean and variance (Welford's update) for a fixed number of
// components, so a multi-component boundary array is estimated from the same
// walks and each component gets its own variance. The first
// `tailComponents` components (the solution's value) also keep their third
// and fourth central sums (Pébay's one-pass update), from which the
// reported variance's own standard error follows: the measure of how far a
// point's error bar can be trusted (ErrorBarReliability.h).
#ifndef GRIDFREE_STATISTICS_RUNNING_STATISTICS_H
#define GRIDFREE_STATISTICS_RUNNING_STATISTICS_H

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace gridfree
{
class RunningStatistics
{
public:
  explicit RunningStatistics(int components = 1, int tailComponents = 0)
    : Mean(components, 0.0)
    , M2(components, 0.0)
    , M3(static_cast<std::size_t>(std::max(0, std::min(tailComponents, components))), 0.0)
    , M4(M3.size(), 0.0)
  {
  }

  void Reset()
  {
    this->Count = 0;
    std::fill(this->Mean.begin(), this->Mean.end(), 0.0);
    std::fill(this->M2.begin(), this->M2.end(), 0.0);
    std::fill(this->M3.begin(), this->M3.end(), 0.0);
    std::fill(this->M4.begin(), this->M4.end(), 0.0);
  }

  // Adds one sample with Components() values. Welford's form stays accurate
  // when the mean is large compared with the spread (e.g. temperatures in K).
  void Add(const double* sample)
  {
    ++this->Count;
    const double invCount = 1.0 / static_cast<double>(this->Count);
    // Higher sums first: they use M2 and M3 before this sample (Pébay 2008,
    // "Formulas for robust, one-pass parallel computation of covariances and
    // arbitrary-order statistical moments", Eq. 1.5 with one sample added).
    const double n = static_cast<double>(this->Count);
    for (std::size_t c = 0; c < this->M3.size(); ++c)
    {
      const double delta = sample[c] - this->Mean[c];
      const double dn = delta * invCount;
      const double dn2 = dn * dn;
      const double term = delta * dn * (n - 1.0);
      this->M4[c] += term * dn2 * (n * n - 3.0 * n + 3.0) + 6.0 * dn2 * this->M2[c] -
        4.0 * dn * this->M3[c];
      this->M3[c] += term * dn * (n - 2.0) - 3.0 * dn * this->M2[c];
    }
    for (std::size_t c = 0; c < this->Mean.size(); ++c)
    {
      const double delta = sample[c] - this->Mean[c];
      this->Mean[c] += delta * invCount;
      this->M2[c] += delta * (sample[c] - this->Mean[c]);
    }
  }

  int Components() const { return static_cast<int>(this->Mean.size()); }
  // Components whose third and fourth central sums are kept.
  int TailComponents() const { return static_cast<int>(this->M3.size()); }
  std::size_t SampleCount() const { return this->Count; }

  // The exact state (count, means and sums of squared deviations), to be
  // kept and restored later: adding more samples to a restored state gives
  // bit for bit what adding all of them in one go would. m3 and m4 hold
  // TailComponents() numbers each (unused when there are none).
  void SaveState(std::size_t& count, double* mean, double* m2, double* m3 = nullptr,
    double* m4 = nullptr) const
  {
    count = this->Count;
    std::copy(this->Mean.begin(), this->Mean.end(), mean);
    std::copy(this->M2.begin(), this->M2.end(), m2);
    if (!this->M3.empty())
    {
      std::copy(this->M3.begin(), this->M3.end(), m3);
      std::copy(this->M4.begin(), this->M4.end(), m4);
    }
  }
  void RestoreState(std::size_t count, const double* mean, const double* m2,
    const double* m3 = nullptr, const double* m4 = nullptr)
  {
    this->Count = count;
    std::copy(mean, mean + this->Mean.size(), this->Mean.begin());
    std::copy(m2, m2 + this->M2.size(), this->M2.begin());
    if (!this->M3.empty())
    {
      std::copy(m3, m3 + this->M3.size(), this->M3.begin());
      std::copy(m4, m4 + this->M4.size(), this->M4.begin());
    }
  }
  double GetMean(int c) const { return this->Mean[c]; }

  // Adds a known constant to every sample of component c already added
  // (the mean moves; the spread, skew and tails do not).
  void ShiftMean(int c, double delta) { this->Mean[c] += delta; }

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

  // M3² / M2³ = G1²/N for a component c < TailComponents(), with G1 the
  // walks' skewness: near 1 − 3/N when all walks but one agree, near 1/2
  // when all but two do, small (below 0.2 at 128 walks) for the skew of
  // ordinary walk values. 0 when the values agree up to round-off
  // (SpreadIsRoundOff); NaN below 3 walks or for a component without
  // higher sums.
  double SkewShare(int c) const
  {
    if (this->Count < 3 || c < 0 || c >= this->TailComponents())
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    const double m2 = this->M2[c];
    if (this->SpreadIsRoundOff(c))
    {
      return 0.0;
    }
    return this->M3[c] * this->M3[c] / (m2 * m2 * m2);
  }

  // Whether component c's values agree up to round-off: a spread below
  // 1e-12 of the mean's size (boundary values interpolated on a triangle
  // differ in their last bits though the data are the same).
  bool SpreadIsRoundOff(int c) const
  {
    const double n = static_cast<double>(std::max<std::size_t>(this->Count, 1));
    const double tolerance = 1e-12 * std::abs(this->Mean[c]);
    return !(this->M2[c] > n * tolerance * tolerance) && !std::isnan(this->M2[c]);
  }

  // The relative standard error of SampleVariance(c) (and so of the
  // variance of the mean), for a component c < TailComponents():
  //   sqrt((κ − (N − 3)/(N − 1)) / N),  κ = N·M4 / M2²,
  // the large-sample standard error of a sample variance over the variance
  // itself. Near 0.09 for normal walk values at 256 walks; near 1 when one
  // walk carries most of the spread (heavy tails). 0 for identical values;
  // NaN below 4 walks or for a component without higher sums.
  double VarianceRelativeError(int c) const
  {
    if (this->Count < 4 || c < 0 || c >= this->TailComponents())
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    const double m2 = this->M2[c];
    if (!(m2 > 0.0))
    {
      return m2 == 0.0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
    }
    const double n = static_cast<double>(this->Count);
    const double kurtosis = n * this->M4[c] / (m2 * m2);
    return std::sqrt(std::max(0.0, kurtosis - (n - 3.0) / (n - 1.0)) / n);
  }

private:
  std::size_t Count = 0;
  std::vector<double> Mean;
  std::vector<double> M2;
  std::vector<double> M3;
  std::vector<double> M4;
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
