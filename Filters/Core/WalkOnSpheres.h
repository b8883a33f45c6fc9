// Walk on spheres for the Dirichlet Laplace problem (paper Sec. 2.2, Eqn. 5).
//
//   Δu = 0 in Ω,  u = g on ∂Ω.
//
// From x_k, jump to a uniform point on the largest empty sphere ∂B(x_k, R_k),
// R_k = dist(x_k, ∂Ω), until R_k < ε; then return g at the closest point x̄_k.
// E[g(x̄_k)] = u(x_0) up to the O(ε) bias of the ε-shell (paper Sec. 6.1).
//
// Two ways a walk may end without reaching the ε-shell are counted, never
// hidden: it takes MaxSteps steps (it then returns g at its current closest
// point, a biased value), or it leaves a far sphere around the boundary, which
// only happens in a region the boundary does not enclose (it then returns 0,
// the value of the exterior problem at infinity; paper Sec. 2.6).
#ifndef GRIDFREE_CORE_WALKONSPHERES_H
#define GRIDFREE_CORE_WALKONSPHERES_H

#include "Boundary.h"
#include "Random.h"
#include "RunningStatistics.h"
#include "SphereSampling.h"
#include "Vector.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
struct WalkSettings
{
  // Absolute stopping tolerance ε: a walk stops once dist(x, ∂Ω) < ε.
  double Epsilon = 1e-4;
  // Steps after which a walk is stopped and counted as truncated.
  int MaxSteps = 10000;
  // The far sphere is centred on the boundary's box with radius
  // EscapeRadiusFactor × box diagonal (at least twice the start distance).
  double EscapeRadiusFactor = 8.0;
};

enum class WalkEnd
{
  Boundary,  // reached the ε-shell: the normal case
  MaxSteps,  // truncated
  Escaped    // left the far sphere
};

// Per-point bookkeeping beside the running statistics of the value.
struct WalkCounters
{
  std::uint64_t Walks = 0;
  std::uint64_t Steps = 0;
  std::uint64_t Escaped = 0;
  std::uint64_t Truncated = 0;

  double MeanSteps() const { return Walks ? double(Steps) / double(Walks) : 0.0; }
  double EscapedFraction() const { return Walks ? double(Escaped) / double(Walks) : 0.0; }
  double TruncatedFraction() const { return Walks ? double(Truncated) / double(Walks) : 0.0; }
};

template <int DIM>
class LaplaceWalkOnSpheres
{
public:
  LaplaceWalkOnSpheres(const Boundary<DIM>& boundary, const WalkSettings& settings)
    : Geometry(boundary)
    , Settings(settings)
    , Sample(boundary.Components())
  {
  }

  // One walk of Eqn. 5 from x. Writes g (Components() numbers) into value.
  WalkEnd Walk(Vec<DIM> x, double escapeRadius, RandomStream& rng, double* value,
    int& steps) const
  {
    const Vec<DIM> center = this->Geometry.Center();
    const double escape2 = escapeRadius * escapeRadius;
    for (steps = 0;; ++steps)
    {
      const double radius = this->Geometry.Distance(x);
      if (radius < this->Settings.Epsilon)
      {
        this->Geometry.Evaluate(this->Geometry.ClosestPoint(x), value);
        return WalkEnd::Boundary;
      }
      if ((x - center).squaredNorm() > escape2)
      {
        for (int c = 0; c < this->Geometry.Components(); ++c)
        {
          value[c] = 0.0;
        }
        return WalkEnd::Escaped;
      }
      if (steps >= this->Settings.MaxSteps)
      {
        this->Geometry.Evaluate(this->Geometry.ClosestPoint(x), value);
        return WalkEnd::MaxSteps;
      }
      x += radius * SampleUnitSphere<DIM>(rng);
    }
  }

  // Runs walks number firstWalk .. firstWalk + walks - 1 from the probe point
  // probeXYZ (its first DIM coordinates are the start point; all three key
  // the random streams) and accumulates them into stats and counters.
  // Non-finite start points yield NaN samples rather than endless walks.
  void EstimatePoint(const double probeXYZ[3], std::uint64_t seed, std::uint64_t firstWalk,
    int walks, RunningStatistics& stats, WalkCounters& counters)
  {
    Vec<DIM> x0;
    bool finite = true;
    for (int i = 0; i < DIM; ++i)
    {
      x0[i] = probeXYZ[i];
      finite = finite && std::isfinite(probeXYZ[i]);
    }
    if (!finite)
    {
      std::fill(this->Sample.begin(), this->Sample.end(),
        std::numeric_limits<double>::quiet_NaN());
      for (int w = 0; w < walks; ++w)
      {
        stats.Add(this->Sample.data());
      }
      counters.Walks += static_cast<std::uint64_t>(walks);
      return;
    }
    const double escapeRadius = std::max(this->Settings.EscapeRadiusFactor *
        std::max(this->Geometry.Diagonal(), this->Settings.Epsilon),
      2.0 * (x0 - this->Geometry.Center()).norm());
    const std::uint64_t key = PointKey(seed, probeXYZ);
    for (int w = 0; w < walks; ++w)
    {
      RandomStream rng(key, firstWalk + static_cast<std::uint64_t>(w));
      int steps = 0;
      const WalkEnd end = this->Walk(x0, escapeRadius, rng, this->Sample.data(), steps);
      stats.Add(this->Sample.data());
      counters.Walks += 1;
      counters.Steps += static_cast<std::uint64_t>(steps);
      counters.Escaped += end == WalkEnd::Escaped ? 1 : 0;
      counters.Truncated += end == WalkEnd::MaxSteps ? 1 : 0;
    }
  }

private:
  const Boundary<DIM>& Geometry;
  WalkSettings Settings;
  std::vector<double> Sample; // scratch: one walk's value (one estimator per thread)
};
} // namespace gridfree

#endif
