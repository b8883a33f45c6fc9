// Shared by the cache tests (BoundaryValueCache.h, SphereCache.h): exact
// solutions in the unit ball (disc) with their gradients and sources, a
// spiral of probe points, and the pooled calibration check (mean z² and the
// largest |z| of estimates against the exact solution).
#ifndef GRIDFREE_TESTING_CACHE_CHECKS_H
#define GRIDFREE_TESTING_CACHE_CHECKS_H

#include "BlockShapes.h"
#include "TestMeshes.h"

#include <gridfree/problem/Problem.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace gridfree
{
namespace testing
{
// u = x² − y² + 0.3 z (3D) or x² − y² + 0.3 y (2D), harmonic.
template <int DIM>
double CacheSaddle(const Vec<DIM>& x)
{
  return x[0] * x[0] - x[1] * x[1] + 0.3 * x[DIM - 1];
}

template <int DIM>
Vec<DIM> CacheSaddleGradient(const Vec<DIM>& x)
{
  Vec<DIM> g = Vec<DIM>::Zero();
  g[0] = 2.0 * x[0];
  g[1] = -2.0 * x[1];
  g[DIM - 1] += 0.3;
  return g;
}

inline WalkSettings CacheLaplace()
{
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  return settings;
}

// Probe points inside the unit ball (disc), clear of the shell.
template <int DIM>
std::vector<std::array<double, 3>> CacheProbe(int count, double radius)
{
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < count; ++i)
  {
    // A deterministic spiral of radii and directions.
    const double t = (i + 0.5) / count;
    const double rho = radius * std::cbrt(t);
    const double phi = 2.399963229728653 * i;
    const double z = DIM == 3 ? 1.0 - 2.0 * t : 0.0;
    const double s = DIM == 3 ? std::sqrt(std::max(0.0, 1.0 - z * z)) : 1.0;
    points.push_back({ rho * s * std::cos(phi), rho * s * std::sin(phi), rho * z });
  }
  return points;
}

struct CachePooled
{
  double SumZ2 = 0.0;
  double MaxAbsZ = 0.0;
  int Count = 0;
  void Add(double estimate, double variance, double exact)
  {
    const double z = (estimate - exact) / std::sqrt(variance);
    SumZ2 += z * z;
    MaxAbsZ = std::max(MaxAbsZ, std::abs(z));
    ++Count;
  }
  double MeanZ2() const { return SumZ2 / Count; }
};


// Adds a cache's answers at `points` (the points it answered) to the pooled
// z-scores of the value and the gradient; returns how many it answered.
template <int DIM, class Evaluation>
std::size_t PoolAnswers(const Evaluation& answer, const std::vector<std::array<double, 3>>& points,
  const Field<DIM>& u, const std::function<Vec<DIM>(const Vec<DIM>&)>& gradient,
  CachePooled& values, CachePooled& gradients)
{
  std::size_t answered = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (answer.InShell[i] || answer.Outside[i])
    {
      continue;
    }
    ++answered;
    Vec<DIM> x;
    for (int a = 0; a < DIM; ++a)
    {
      x[a] = points[i][static_cast<std::size_t>(a)];
    }
    values.Add(answer.Value[i], answer.ValueVariance[i], u(x));
    const Vec<DIM> exact = gradient(x);
    for (int a = 0; a < DIM; ++a)
    {
      gradients.Add(answer.Gradient[i * DIM + a], answer.GradientVariance[i * DIM + a], exact[a]);
    }
  }
  return answered;
}

inline void ExpectPooledCalibrated(const CachePooled& values, const CachePooled& gradients)
{
  EXPECT_LT(values.MaxAbsZ, 5.0);
  EXPECT_GT(values.MeanZ2(), 0.7);
  EXPECT_LT(values.MeanZ2(), 1.4);
  EXPECT_LT(gradients.MaxAbsZ, 5.0);
  EXPECT_GT(gradients.MeanZ2(), 0.7);
  EXPECT_LT(gradients.MeanZ2(), 1.4);
}

// An equation with its exact solution u, ∇u and the source f of Δu − c·u = f.
template <int DIM>
struct CacheCase
{
  Equation Kind = Equation::Laplace;
  double Screening = 0.0;
  Field<DIM> U = CacheSaddle<DIM>;
  std::function<Vec<DIM>(const Vec<DIM>&)> Gradient = CacheSaddleGradient<DIM>;
  Field<DIM> F; // empty: none
};

// Poisson: u = |x|² + 0.3 x (Δu = 2·DIM); the source's volume integral
// joins the boundary's.
template <int DIM>
CacheCase<DIM> CachePoisson()
{
  CacheCase<DIM> with;
  with.Kind = Equation::Poisson;
  with.U = [](const Vec<DIM>& x) { return x.squaredNorm() + 0.3 * x[0]; };
  with.Gradient = [](const Vec<DIM>& x) {
    Vec<DIM> g = 2.0 * x;
    g[0] += 0.3;
    return g;
  };
  with.F = [](const Vec<DIM>&) { return 2.0 * DIM; };
  return with;
}

// Screened Poisson, c = 4: u = e^{2x} + |x|² (Δu − 4u = 2·DIM − 4|x|²).
template <int DIM>
CacheCase<DIM> CacheScreened()
{
  CacheCase<DIM> with;
  with.Kind = Equation::ScreenedPoisson;
  with.Screening = 4.0;
  with.U = [](const Vec<DIM>& x) { return std::exp(2.0 * x[0]) + x.squaredNorm(); };
  with.Gradient = [](const Vec<DIM>& x) {
    Vec<DIM> g = 2.0 * x;
    g[0] += 2.0 * std::exp(2.0 * x[0]);
    return g;
  };
  with.F = [](const Vec<DIM>& x) { return 2.0 * DIM - 4.0 * x.squaredNorm(); };
  return with;
}
// The L of three unit cells (squares, or cubes 1 deep) with a reflex edge
// (corner): a shape the ball and disc tests do not use.
template <int DIM>
SimplexMesh<DIM> MakeCacheL()
{
  std::vector<Cell<DIM>> cells(3);
  cells[1][0] = 1;
  cells[2][1] = 1;
  return MakeBlockShape<DIM>(cells, DIM == 3 ? 12 : 64);
}

// A 9 × 9 grid of points of the L (z = 0.5) from `first` in steps of
// `step`, those with x or y below `corner`.
inline std::vector<std::array<double, 3>> CacheLGrid(double first, double step, double corner)
{
  std::vector<std::array<double, 3>> points;
  for (int j = 0; j < 9; ++j)
  {
    for (int i = 0; i < 9; ++i)
    {
      const double x = first + step * i, y = first + step * j;
      if (x < corner || y < corner)
      {
        points.push_back({ x, y, 0.5 });
      }
    }
  }
  return points;
}
} // namespace testing
} // namespace gridfree

#endif
