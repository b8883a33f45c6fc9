// Shared machinery of the statistical tests: random probe points, and the
// accuracy + calibration check of an estimator against closed forms
// (DESIGN.md §3): |z| < 5 at every point and mean z² near 1, where
// z = (estimate − exact) / sqrt(reported variance of the mean).
#ifndef GRIDFREE_TESTING_ESTIMATORCHECKS_H
#define GRIDFREE_TESTING_ESTIMATORCHECKS_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/sources/SourceTerms.h>
#include "TestMeshes.h"
#include <gridfree/estimators/WalkOnSpheres.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace gridfree
{
namespace testing
{
struct Calibration
{
  double MeanZ2 = 0.0;
  double MaxAbsZ = 0.0;
  int Points = 0;
  double MeanSteps = 0.0;
  double EscapedFraction = 0.0;
  double TruncatedFraction = 0.0;
};

// The unit sphere (20480 triangles) or the unit circle (4096 segments): the
// domain of most closed-form tests.
template <int DIM>
SimplexMesh<DIM> UnitSphereMesh()
{
  if constexpr (DIM == 3)
  {
    return MakeIcosphere(5);
  }
  else
  {
    return MakeCircle(4096);
  }
}

inline void ExpectCalibrated(const Calibration& c, int minimumPoints = 500)
{
  EXPECT_GE(c.Points, minimumPoints);
  EXPECT_LT(c.MaxAbsZ, 5.0);
  EXPECT_GT(c.MeanZ2, 0.7);
  EXPECT_LT(c.MeanZ2, 1.4);
}

template <int DIM>
std::vector<Vec<DIM>> RandomPointsInBall(
  int count, double radius, std::uint32_t seed, double innerRadius = 0.0)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-radius, radius);
  std::vector<Vec<DIM>> points;
  while (static_cast<int>(points.size()) < count)
  {
    Vec<DIM> p;
    for (int i = 0; i < DIM; ++i)
    {
      p[i] = u(rng);
    }
    if (p.norm() < radius && p.norm() >= innerRadius)
    {
      points.push_back(p);
    }
  }
  return points;
}

// Each point p (inside a closed surface about the origin, at least 0.9
// from it) moved outwards along the ray from the origin, from 0.9·p/|p| in
// steps of 10⁻⁵, until `distance` (to the surface, or to the part of it
// that matters) is at most `gap`: points a gap from the surface.
template <class Distance>
std::vector<Vec3> PointsAtGap(const std::vector<Vec3>& from, double gap, const Distance& distance)
{
  std::vector<Vec3> near;
  for (const Vec3& p : from)
  {
    const Vec3 d = p.normalized();
    double t = 0.9;
    while (distance((t + 1e-5) * d) > gap)
    {
      t += 1e-5;
    }
    near.push_back(t * d);
  }
  return near;
}

template <int DIM>
std::vector<Vec<DIM>> RandomPointsInBox(int count, double half, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<Vec<DIM>> points(count);
  for (Vec<DIM>& p : points)
  {
    for (int i = 0; i < DIM; ++i)
    {
      p[i] = u(rng);
    }
  }
  return points;
}

// Points as a batch's probe: three coordinates each, z = 0 in 2D.
template <int DIM>
std::vector<std::array<double, 3>> AsProbe(const std::vector<Vec<DIM>>& points)
{
  std::vector<std::array<double, 3>> probe;
  for (const Vec<DIM>& p : points)
  {
    std::array<double, 3> xyz = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < DIM; ++k)
    {
      xyz[k] = p[k];
    }
    probe.push_back(xyz);
  }
  return probe;
}

// Boundary values: the fields sampled at the mesh's vertices, side by side.
template <int DIM>
Boundary<DIM> MakeBoundary(const SimplexMesh<DIM>& mesh, const std::vector<Field<DIM>>& fields)
{
  std::vector<double> values;
  for (const auto& v : mesh.Vertices)
  {
    for (const Field<DIM>& f : fields)
    {
      values.push_back(f(v));
    }
  }
  Boundary<DIM> boundary;
  boundary.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points,
    static_cast<int>(fields.size()), values);
  return boundary;
}

// A volume source from a plain function (stateless, so threads may share it).
template <int DIM>
class FunctionSource : public VolumeSource<DIM>
{
public:
  FunctionSource(Field<DIM> f, int components = 1)
    : F(std::move(f))
    , Components(components)
  {
  }
  // A source that vanishes (numerically) outside a box.
  FunctionSource(Field<DIM> f, const Vec<DIM>& boxMin, const Vec<DIM>& boxMax)
    : F(std::move(f))
    , Components(1)
    , Bounded(true)
    , Min(boxMin)
    , Max(boxMax)
  {
  }
  void Evaluate(const Vec<DIM>& y, double* out) override
  {
    const double value = this->F(y);
    for (int c = 0; c < this->Components; ++c)
    {
      out[c] = value;
    }
  }
  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    boxMin = this->Min;
    boxMax = this->Max;
    return this->Bounded;
  }

private:
  Field<DIM> F;
  int Components;
  bool Bounded = false;
  Vec<DIM> Min = Vec<DIM>::Zero();
  Vec<DIM> Max = Vec<DIM>::Zero();
};

// Estimates every output component at `points` with `walks` walks (on two
// threads) and returns one Calibration per entry of `exact`.
template <int DIM>
std::vector<Calibration> CheckEstimator(const Boundary<DIM>& boundary,
  const WalkSettings& settings, const std::vector<Vec<DIM>>& points,
  const std::vector<Field<DIM>>& exact, int walks, std::uint64_t seed,
  VolumeSource<DIM>* volume = nullptr,
  const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>())
{
  const int components = static_cast<int>(exact.size());
  std::vector<double> mean(points.size() * components), variance(points.size() * components);
  std::vector<WalkCounters> counters(points.size());
  ParallelForWithProgress(points.size(), 2,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      WalkOnSpheresEstimator<DIM> estimator(boundary, settings, volume, concentrated);
      RunningStatistics stats(estimator.OutputComponents());
      for (std::size_t i = begin; i < end; ++i)
      {
        double xyz[3] = { 0, 0, 0 };
        for (int k = 0; k < DIM; ++k)
        {
          xyz[k] = points[i][k];
        }
        stats.Reset();
        estimator.EstimatePoint(xyz, seed, 0, walks, stats, counters[i]);
        for (int c = 0; c < components; ++c)
        {
          mean[i * components + c] = stats.GetMean(c);
          variance[i * components + c] = stats.VarianceOfMean(c);
        }
      }
    },
    nullptr);
  std::vector<Calibration> result(components);
  for (int c = 0; c < components; ++c)
  {
    Calibration& r = result[c];
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const double z = (mean[i * components + c] - exact[c](points[i])) /
        std::sqrt(variance[i * components + c]);
      r.MeanZ2 += z * z;
      r.MaxAbsZ = std::max(r.MaxAbsZ, std::isfinite(z) ? std::abs(z) : 1e300);
      r.MeanSteps += counters[i].MeanSteps();
      r.EscapedFraction += counters[i].EscapedFraction();
      r.TruncatedFraction += counters[i].TruncatedFraction();
      ++r.Points;
    }
    r.MeanZ2 /= r.Points;
    r.MeanSteps /= r.Points;
    r.EscapedFraction /= r.Points;
    r.TruncatedFraction /= r.Points;
  }
  return result;
}
// One quantity a derivative test checks: a slot of the sample layout and the
// exact value there.
template <int DIM>
struct SlotCheck
{
  int Slot;
  Field<DIM> Exact;
};

// Result of a derivative run: per-point means and variances of every slot.
struct DerivativeRun
{
  std::vector<double> Mean;
  std::vector<double> Variance;
  std::vector<DerivativeStatus> Status;
  int Size = 0;
};

// Runs `walks` walks at every point (on `threads` threads) with an
// estimator from makeEstimator() per thread, whose samples have `size`
// slots; a point's status is what its EstimatePoint returns.
template <int DIM, class MakeEstimator>
DerivativeRun RunPointEstimator(const std::vector<Vec<DIM>>& points, int size, int walks,
  std::uint64_t seed, int threads, MakeEstimator&& makeEstimator)
{
  DerivativeRun run;
  run.Size = size;
  run.Mean.resize(points.size() * run.Size);
  run.Variance.resize(points.size() * run.Size);
  run.Status.resize(points.size());
  ParallelForWithProgress(points.size(), threads,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      auto estimator = makeEstimator();
      RunningStatistics stats(run.Size);
      WalkCounters counters;
      for (std::size_t i = begin; i < end; ++i)
      {
        double xyz[3] = { 0, 0, 0 };
        for (int k = 0; k < DIM; ++k)
        {
          xyz[k] = points[i][k];
        }
        stats.Reset();
        run.Status[i] = estimator.EstimatePoint(xyz, seed, 0, walks, stats, counters);
        for (int c = 0; c < run.Size; ++c)
        {
          run.Mean[i * run.Size + c] = stats.GetMean(c);
          run.Variance[i * run.Size + c] = stats.VarianceOfMean(c);
        }
      }
    },
    nullptr);
  return run;
}

// Estimator: DerivativeWalkOnSpheres<DIM> or another continuation of it
// (StarDerivativeWalks<DIM> with a MixedBoundary).
template <int DIM, class Estimator = DerivativeWalkOnSpheres<DIM>>
DerivativeRun RunDerivativeEstimator(const typename Estimator::BoundaryType& boundary,
  const WalkSettings& settings,
  const DerivativeRequest& request, const std::vector<Vec<DIM>>& points, int walks,
  std::uint64_t seed, VolumeSource<DIM>* volume = nullptr,
  const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>(),
  int threads = 2)
{
  const int size = Estimator(boundary, settings, request, volume, concentrated).Layout().Size;
  return RunPointEstimator<DIM>(points, size, walks, seed, threads,
    [&]() { return Estimator(boundary, settings, request, volume, concentrated); });
}

// Calibration of each checked slot over all points of a run.
template <int DIM>
std::vector<Calibration> Calibrate(
  const DerivativeRun& run, const std::vector<Vec<DIM>>& points, const std::vector<SlotCheck<DIM>>& checks)
{
  std::vector<Calibration> result(checks.size());
  for (std::size_t k = 0; k < checks.size(); ++k)
  {
    Calibration& r = result[k];
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const std::size_t at = i * run.Size + checks[k].Slot;
      const double z = (run.Mean[at] - checks[k].Exact(points[i])) / std::sqrt(run.Variance[at]);
      r.MeanZ2 += z * z;
      r.MaxAbsZ = std::max(r.MaxAbsZ, std::isfinite(z) ? std::abs(z) : 1e300);
      ++r.Points;
    }
    r.MeanZ2 /= r.Points;
  }
  return result;
}
} // namespace testing
} // namespace gridfree

#endif
