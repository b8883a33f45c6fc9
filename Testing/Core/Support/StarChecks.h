// Walk on stars at a list of points against a closed form: the calibration
// of the estimates (EstimatorChecks.h) and the back-face hits, for the
// walk-on-stars tests that check one solution on one boundary.
#ifndef GRIDFREE_TESTING_STARCHECKS_H
#define GRIDFREE_TESTING_STARCHECKS_H

#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/stars/WalkOnStars.h>
#include <gridfree/statistics/RunningStatistics.h>

#include "EstimatorChecks.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gridfree
{
namespace testing
{
// `walks` walks at every point (two threads, walk seed `seed`): the
// calibration against `exact`, and the estimators' back-face hits summed
// into `backHits`.
template <int DIM>
Calibration CalibrateStars(const MixedBoundary<DIM>& boundary, const WalkSettings& settings,
  const std::vector<Vec<DIM>>& points, const Field<DIM>& exact, int walks, std::uint64_t seed,
  std::uint64_t& backHits)
{
  std::vector<double> mean(points.size()), variance(points.size());
  std::atomic<std::uint64_t> hits{ 0 };
  ParallelForWithProgress(points.size(), 2,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      WalkOnStarsEstimator<DIM> estimator(boundary, settings);
      RunningStatistics stats(1);
      for (std::size_t i = begin; i < end; ++i)
      {
        const double xyz[3] = { points[i][0], points[i][1], DIM == 3 ? points[i][DIM - 1] : 0.0 };
        stats.Reset();
        WalkCounters counters;
        estimator.EstimatePoint(xyz, seed, 0, walks, stats, counters);
        mean[i] = stats.GetMean(0);
        variance[i] = stats.VarianceOfMean(0);
      }
      hits += estimator.BackFaceHits();
    },
    nullptr);
  backHits = hits.load();
  Calibration c;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double z = (mean[i] - exact(points[i])) / std::sqrt(variance[i]);
    c.MeanZ2 += z * z / static_cast<double>(points.size());
    c.MaxAbsZ = std::max(c.MaxAbsZ, std::isfinite(z) ? std::abs(z) : 1e300);
    ++c.Points;
  }
  return c;
}
} // namespace testing
} // namespace gridfree

#endif
