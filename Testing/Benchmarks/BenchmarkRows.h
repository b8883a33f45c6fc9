// One row of the walk benchmarks' tables (CSG and walk on stars): an
// estimator run at every point against a closed form, one thread, with its
// walks per second, steps per walk, RMSE (and the gradient's) and the
// set-up time before it.
#ifndef GRIDFREE_BENCHMARKS_BENCHMARKROWS_H
#define GRIDFREE_BENCHMARKS_BENCHMARKROWS_H

#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/math/Vector.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace gridfree
{
namespace bench
{
struct Row
{
  std::string Name;
  double WalksPerSecond = 0.0;
  double StepsPerWalk = 0.0;
  double Rmse = 0.0;
  double SetupSeconds = 0.0;
  double GradientRmse = -1.0; // |∇u error| over the points; < 0: not estimated
  int Points = 0;
  int Walks = 0; // per point

  // Seconds of all the row's walks.
  double Seconds() const
  {
    return this->WalksPerSecond > 0.0
      ? static_cast<double>(this->Points) * this->Walks / this->WalksPerSecond
      : 0.0;
  }
};

inline double SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// `walks` walks of `estimator` (any with EstimatePoint) at every point, seed 7.
template <class Estimator>
Row RunEstimator(const std::string& name, Estimator& estimator, const std::vector<Vec3>& points,
  int walks, const std::function<double(const Vec3&)>& exact)
{
  const auto start = std::chrono::steady_clock::now();
  double squared = 0.0;
  WalkCounters total;
  for (const Vec3& p : points)
  {
    const double xyz[3] = { p[0], p[1], p[2] };
    RunningStatistics stats(1);
    WalkCounters counters;
    estimator.EstimatePoint(xyz, 7, 0, walks, stats, counters);
    const double e = stats.GetMean(0) - exact(p);
    squared += e * e;
    total.Add(counters);
  }
  Row row;
  row.Name = name;
  row.WalksPerSecond = static_cast<double>(total.Walks) / SecondsSince(start);
  row.StepsPerWalk = total.MeanSteps();
  row.Rmse = std::sqrt(squared / static_cast<double>(points.size()));
  row.Points = static_cast<int>(points.size());
  row.Walks = walks;
  return row;
}

// The same with a derivative estimator (its Layout()): the value's RMSE and
// the gradient's, |estimate − gradient| over the points.
template <class Estimator>
Row RunGradientEstimator(const std::string& name, Estimator& estimator,
  const std::vector<Vec3>& points, int walks, const std::function<double(const Vec3&)>& exact,
  const std::function<Vec3(const Vec3&)>& gradient)
{
  const auto start = std::chrono::steady_clock::now();
  const auto layout = estimator.Layout();
  double squared = 0.0, gradientSquared = 0.0;
  WalkCounters total;
  for (const Vec3& p : points)
  {
    const double xyz[3] = { p[0], p[1], p[2] };
    RunningStatistics stats(layout.Size);
    WalkCounters counters;
    estimator.EstimatePoint(xyz, 7, 0, walks, stats, counters);
    const double e = stats.GetMean(layout.Value) - exact(p);
    squared += e * e;
    const Vec3 g = gradient(p);
    for (int d = 0; d < 3; ++d)
    {
      const double ge = stats.GetMean(layout.Gradient + d) - g[d];
      gradientSquared += ge * ge;
    }
    total.Add(counters);
  }
  Row row;
  row.Name = name;
  row.WalksPerSecond = static_cast<double>(total.Walks) / SecondsSince(start);
  row.StepsPerWalk = total.MeanSteps();
  const double n = static_cast<double>(points.size());
  row.Rmse = std::sqrt(squared / n);
  row.GradientRmse = std::sqrt(gradientSquared / n);
  row.Points = static_cast<int>(points.size());
  row.Walks = walks;
  return row;
}
} // namespace bench
} // namespace gridfree

#endif
