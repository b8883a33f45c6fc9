// Cross fields from a complex "fourth power" function (paper Sec. 6.5).
//
// A 2D cross field is encoded by ψ: Ω → C, harmonic, with boundary values
// ν⁴ (ν the unit outward normal as a complex number): raising to the fourth
// power identifies the four directions of a cross, so a smooth ψ gives a
// smooth cross field. At a point the cross directions are the fourth roots
// of ψ/|ψ|; singularities are the zeros of ψ, and the winding number n of ψ
// around a zero is the cross-field index in quarter units (index n/4).
//
// Here ψ and its gradient come from a Monte Carlo estimator that is expensive
// per call but evaluates many points in parallel, and every value is noisy.
// So everything below is written against a batch evaluator: each iteration of
// a search or of a curve integration gathers the points of all seeds or curves
// still moving and makes one call. Decisions that compare noisy values allow
// for the noise the estimator reports (PsiVariance), and the index is an
// average over a circle rather than a value at one point:
//
// * Singularities: gradient descent on |ψ|² from caller-given seeds with
//   normalised, per-seed adaptive steps; seeds stop at the noise floor, when
//   their step collapses, or when the gradient vanishes. Seeds that stopped
//   where |ψ| is small relative to its typical size (and to the noise) are
//   clustered; the others sit at minima of |ψ| that are not zeros.
// * Index: the paper's n = −i (|x − x*| / ψ) D_u ψ with u the counter-clockwise
//   tangent. On a circle around x* this is −i ∂_φ log ψ, whose mean over the
//   circle is the winding number of ψ around that circle: exact for any zero
//   inside it, so an x* off by less than the radius does not matter, and the
//   trapezoidal mean over M points converges spectrally. Noise averages out
//   over the M samples.
// * Separatrices: from a zero of winding n, the cross is aligned with the
//   radial direction e^{iθ} where arg ψ(x* + ρ e^{iθ}) ≡ 4θ; arg ψ − 4θ winds
//   n − 4 times around the circle, so there are |4 − n| such directions. They
//   are traced with Heun steps, each stage one batch call for all curves.
//
// Nothing here is random: the caller chooses the seeds.
#ifndef GRIDFREE_APPLICATIONS_CROSS_FIELD_H
#define GRIDFREE_APPLICATIONS_CROSS_FIELD_H

#include <gridfree/applications/LockstepStreamlines.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

namespace gridfree
{
// One estimate of ψ at a point.
struct CrossFieldSample
{
  std::complex<double> Psi = 0.0;
  Vec2 GradRe = Vec2::Zero(); // ∇ Re ψ
  Vec2 GradIm = Vec2::Zero(); // ∇ Im ψ
  // Variance of the estimate of ψ: Var(Re ψ) + Var(Im ψ).
  double PsiVariance = 0.0;
  // Distance to the boundary; 0 or negative on/outside it, NaN if unknown.
  double BoundaryDistance = std::numeric_limits<double>::infinity();
  // False: the point could not be evaluated (outside the domain, ...).
  bool Valid = true;
};

// Evaluates all `points` at once into `out` (resized to points.size()).
// Returning false aborts the computation that called it.
using CrossFieldEvaluator =
  std::function<bool(const std::vector<Vec2>& points, std::vector<CrossFieldSample>& out)>;

// ν⁴ for the normalised `normal` as a complex number; 0 for a zero or
// non-finite vector.
inline std::complex<double> EncodeNormalFourth(const Vec2& normal)
{
  const double length = normal.norm();
  if (!(length > 0.0) || !std::isfinite(length))
  {
    return 0.0;
  }
  const std::complex<double> nu(normal.x() / length, normal.y() / length);
  const std::complex<double> square = nu * nu;
  return square * square;
}

// The four unit directions of the cross encoded by ψ, at angles
// arg(ψ)/4 + kπ/2. False (and zero vectors) when ψ is zero or not finite.
inline bool CrossDirections(const std::complex<double>& psi, std::array<Vec2, 4>& out)
{
  const double magnitude = std::abs(psi);
  if (!(magnitude > 0.0) || !std::isfinite(magnitude))
  {
    out.fill(Vec2::Zero());
    return false;
  }
  const double base = std::arg(psi) / 4.0;
  for (int k = 0; k < 4; ++k)
  {
    const double angle = base + k * (M_PI / 2.0);
    out[k] = Vec2(std::cos(angle), std::sin(angle));
  }
  return true;
}

// The cross direction of ψ nearest to `tangent` (unit result, within 45° of
// it). False when ψ is zero or either input is not finite.
inline bool AlignedCrossDirection(const std::complex<double>& psi, const Vec2& tangent, Vec2& out)
{
  const double length = tangent.norm();
  const double magnitude = std::abs(psi);
  if (!(length > 0.0) || !std::isfinite(length) || !(magnitude > 0.0) || !std::isfinite(magnitude))
  {
    out = Vec2::Zero();
    return false;
  }
  // The cross directions are the d with d⁴ = ψ/|ψ|. Writing d = τ e^{iδ/4}
  // with τ the tangent, δ = arg(ψ τ̄⁴) ∈ (−π, π] picks the root within π/4
  // of τ, without comparing four candidates.
  const std::complex<double> tau(tangent.x() / length, tangent.y() / length);
  const std::complex<double> tauSquare = std::conj(tau * tau);
  const double delta = std::arg(psi * tauSquare * tauSquare);
  const std::complex<double> d = tau * std::polar(1.0, delta / 4.0);
  out = Vec2(d.real(), d.imag());
  return true;
}

namespace detail
{
// Angle into (−π, π].
inline double WrapAngle(double angle)
{
  double wrapped = std::remainder(angle, 2.0 * M_PI);
  if (wrapped <= -M_PI)
  {
    wrapped += 2.0 * M_PI;
  }
  return wrapped;
}

inline bool IsFinite(const Vec2& v)
{
  return std::isfinite(v.x()) && std::isfinite(v.y());
}

// A sample the algorithms can use: valid, finite, and not on or outside the
// boundary (an unknown, NaN, distance is accepted).
inline bool IsUsable(const CrossFieldSample& s)
{
  return s.Valid && std::isfinite(s.Psi.real()) && std::isfinite(s.Psi.imag()) &&
    IsFinite(s.GradRe) && IsFinite(s.GradIm) && !(s.BoundaryDistance <= 0.0);
}

inline double NoiseFloor(const CrossFieldSample& s, double factor)
{
  return factor * std::sqrt(std::max(s.PsiVariance, 0.0));
}

// One batch call, counted. An answer of the wrong size is a failure: the
// caller could not tell which sample belongs to which point.
inline bool EvaluateBatch(const CrossFieldEvaluator& evaluator, const std::vector<Vec2>& points,
  std::vector<CrossFieldSample>& out, std::size_t& calls, std::size_t& evaluatedPoints)
{
  out.assign(points.size(), CrossFieldSample{});
  ++calls;
  evaluatedPoints += points.size();
  return evaluator(points, out) && out.size() == points.size();
}

// Median of values (reorders them); the mean of the two middle ones for an
// even count.
inline double Median(std::vector<double>& values)
{
  const std::size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + half, values.end());
  double median = values[half];
  if (values.size() % 2 == 0)
  {
    median = 0.5 * (median + *std::max_element(values.begin(), values.begin() + half));
  }
  return median;
}
} // namespace detail

// Settings of FindSingularities, in the problem's length units (scale them
// with the domain) and in the units of ψ.
struct SingularitySettings
{
  int MaxIterations = 200;   // descent iterations (= batch calls) at most
  double InitialStep = 0.01; // first step of every seed
  double MaxStep = 0.1;
  double MinStep = 1e-6;    // a seed whose step falls below this has stalled
  double StepGrowth = 1.5;  // step factor after |ψ|² decreased
  double StepShrink = 0.5;  // step factor after it did not
  // A step never exceeds this fraction of the boundary distance, so that
  // trial points stay inside (the distance is 1-Lipschitz).
  double BoundaryStepFraction = 0.5;
  // A seed has converged once |ψ| < NoiseFloor · sqrt(PsiVariance): below,
  // comparisons of |ψ| are decided by noise.
  double NoiseFloor = 3.0;
  // Stopped seeds closer than this are one singularity (single linkage).
  double MergeRadius = 0.02;
  // A stopped seed is at a zero of ψ only if its |ψ| is below
  // RelativeZeroThreshold · typical |ψ| (plus its noise floor); others, at
  // minima of |ψ| that are not zeros, are not clustered. Typical |ψ| is
  // TypicalPsi if positive, else the median of |ψ| at the seeds.
  double RelativeZeroThreshold = 0.05;
  double TypicalPsi = 0.0;
  // Index circle: radius IndexRadius, clamped to IndexBoundaryFraction of the
  // boundary distance and to half the distance to the nearest other
  // singularity; IndexSamples points on it.
  double IndexRadius = 0.05;
  double IndexBoundaryFraction = 0.5;
  int IndexSamples = 32;
  // Keep clusters whose winding number is 0 (not cross-field singularities).
  bool KeepZeroIndex = false;
};

struct Singularity
{
  Vec2 Position = Vec2::Zero();
  // Winding number of ψ = round(mean n); the cross-field index is Index / 4.
  int Index = 0;
  double IndexResidual = 0.0;  // Re(mean n) − Index: small when resolved
  double IndexImaginary = 0.0; // Im(mean n): tends to 0, a noise indicator
  // Winding of arg ψ summed over the same circle samples; disagreement with
  // Index means the circle was too coarse or too noisy.
  int PhaseWinding = 0;
  double PsiMagnitude = 0.0; // |ψ| estimated at Position
  int SeedCount = 0;         // seeds that stopped in this cluster
  double Radius = 0.0;       // radius of the index circle used
  int IndexSampleCount = 0;  // usable samples on that circle
};

struct SingularitySearchStatistics
{
  std::size_t EvaluatorCalls = 0;
  std::size_t EvaluatedPoints = 0;
  int Iterations = 0;
  int SeedsInvalid = 0;       // not finite, or invalid at the seed
  int SeedsConverged = 0;     // reached the noise floor
  int SeedsStalled = 0;       // step below MinStep, or zero gradient
  int SeedsMaxIterations = 0; // still moving at the end: not clustered
  int SeedsNotZero = 0;       // stopped where |ψ| is not small: not clustered
  int ClustersUnresolved = 0; // fewer than half the circle usable, dropped
  int ClustersZeroIndex = 0;  // winding 0, dropped unless KeepZeroIndex
  bool Aborted = false;       // the evaluator failed; nothing is returned
};

// Zeros of ψ reached by gradient descent on |ψ|² from `seeds`, with their
// winding numbers. One evaluator call for the seeds, one per iteration for
// all seeds still moving, and one for all index circles.
inline std::vector<Singularity> FindSingularities(const CrossFieldEvaluator& evaluator,
  const std::vector<Vec2>& seeds, const SingularitySettings& settings = {},
  SingularitySearchStatistics* statistics = nullptr)
{
  SingularitySearchStatistics local;
  SingularitySearchStatistics& stats = statistics ? *statistics : local;
  stats = SingularitySearchStatistics{};
  std::vector<Singularity> result;
  if (!evaluator || seeds.empty())
  {
    return result;
  }

  enum class State
  {
    Active,
    Converged,
    Stalled,
    MaxIterations,
    Invalid
  };
  struct Seed
  {
    Vec2 X = Vec2::Zero();
    CrossFieldSample Sample;
    double Step = 0.0;
    double TrialStep = 0.0;
    State Status = State::Invalid;
  };
  std::vector<Seed> walkers(seeds.size());
  std::vector<Vec2> points;
  std::vector<std::size_t> owners;
  std::vector<CrossFieldSample> samples;
  const auto belowNoiseFloor = [&settings](const CrossFieldSample& s) {
    return std::abs(s.Psi) < detail::NoiseFloor(s, settings.NoiseFloor);
  };

  for (std::size_t i = 0; i < seeds.size(); ++i)
  {
    if (detail::IsFinite(seeds[i]))
    {
      points.push_back(seeds[i]);
      owners.push_back(i);
    }
  }
  if (!points.empty() &&
    !detail::EvaluateBatch(evaluator, points, samples, stats.EvaluatorCalls, stats.EvaluatedPoints))
  {
    stats.Aborted = true;
    return result;
  }
  std::vector<double> initialMagnitudes;
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    Seed& w = walkers[owners[k]];
    w.X = points[k];
    w.Sample = samples[k];
    w.Step = settings.InitialStep;
    if (!detail::IsUsable(w.Sample))
    {
      continue;
    }
    initialMagnitudes.push_back(std::abs(w.Sample.Psi));
    w.Status = belowNoiseFloor(w.Sample) ? State::Converged : State::Active;
  }
  const double typicalPsi = settings.TypicalPsi > 0.0 ? settings.TypicalPsi
    : initialMagnitudes.empty()                       ? 0.0
                                                      : detail::Median(initialMagnitudes);

  for (int iteration = 0; iteration < settings.MaxIterations; ++iteration)
  {
    points.clear();
    owners.clear();
    for (std::size_t i = 0; i < walkers.size(); ++i)
    {
      Seed& w = walkers[i];
      if (w.Status != State::Active)
      {
        continue;
      }
      // −∇|ψ|²/2 = −(Re ψ ∇Re ψ + Im ψ ∇Im ψ); only its direction is used,
      // since its length vanishes at a zero of any order and the step size
      // is adapted anyway.
      const Vec2 descent =
        -(w.Sample.Psi.real() * w.Sample.GradRe + w.Sample.Psi.imag() * w.Sample.GradIm);
      const double length = descent.norm();
      if (!(length > 0.0) || !std::isfinite(length))
      {
        w.Status = State::Stalled;
        continue;
      }
      double step = std::min(w.Step, settings.MaxStep);
      if (std::isfinite(w.Sample.BoundaryDistance))
      {
        step = std::min(step, settings.BoundaryStepFraction * w.Sample.BoundaryDistance);
      }
      if (!(step >= settings.MinStep))
      {
        w.Status = State::Stalled;
        continue;
      }
      w.TrialStep = step;
      points.push_back(w.X + (step / length) * descent);
      owners.push_back(i);
    }
    if (points.empty())
    {
      break;
    }
    ++stats.Iterations;
    if (!detail::EvaluateBatch(evaluator, points, samples, stats.EvaluatorCalls, stats.EvaluatedPoints))
    {
      stats.Aborted = true;
      return result;
    }
    for (std::size_t k = 0; k < points.size(); ++k)
    {
      Seed& w = walkers[owners[k]];
      const CrossFieldSample& trial = samples[k];
      if (detail::IsUsable(trial) && std::norm(trial.Psi) < std::norm(w.Sample.Psi))
      {
        w.X = points[k];
        w.Sample = trial;
        w.Step = std::min(w.TrialStep * settings.StepGrowth, settings.MaxStep);
        if (belowNoiseFloor(w.Sample))
        {
          w.Status = State::Converged;
        }
      }
      else
      {
        // An unusable trial point (outside, say) is treated as a failed step
        // rather than the end of the seed: a shorter step may stay inside.
        w.Step = w.TrialStep * settings.StepShrink;
        if (w.Step < settings.MinStep)
        {
          w.Status = State::Stalled;
        }
      }
    }
  }

  // Only seeds where |ψ| became small are clustered: a seed stalled at a
  // minimum of |ψ| that is not a zero, or at a saddle of |ψ|² between two
  // zeros where noise hides the gradient, would otherwise chain distinct
  // zeros into one cluster. The threshold allows for the noise of the seed's
  // own estimate.
  const auto isSmall = [&](const CrossFieldSample& s) {
    return std::abs(s.Psi) <= settings.RelativeZeroThreshold * typicalPsi +
      detail::NoiseFloor(s, settings.NoiseFloor);
  };
  std::vector<std::size_t> stopped;
  for (std::size_t i = 0; i < walkers.size(); ++i)
  {
    switch (walkers[i].Status)
    {
      case State::Active:
        walkers[i].Status = State::MaxIterations;
        ++stats.SeedsMaxIterations;
        continue;
      case State::Converged:
        ++stats.SeedsConverged;
        break;
      case State::Stalled:
        ++stats.SeedsStalled;
        break;
      default:
        ++stats.SeedsInvalid;
        continue;
    }
    if (isSmall(walkers[i].Sample))
    {
      stopped.push_back(i);
    }
    else
    {
      ++stats.SeedsNotZero;
    }
  }

  // Single-linkage clusters (union-find); sorting by x bounds the pairs to
  // compare to those whose x differ by at most the merge radius.
  std::vector<std::size_t> parent(stopped.size());
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  const auto find = [&parent](std::size_t a) {
    while (parent[a] != a)
    {
      parent[a] = parent[parent[a]];
      a = parent[a];
    }
    return a;
  };
  std::vector<std::size_t> byX(stopped.size());
  std::iota(byX.begin(), byX.end(), std::size_t(0));
  std::sort(byX.begin(), byX.end(), [&](std::size_t a, std::size_t b) {
    return walkers[stopped[a]].X.x() < walkers[stopped[b]].X.x();
  });
  for (std::size_t a = 0; a < byX.size(); ++a)
  {
    const Vec2& xa = walkers[stopped[byX[a]]].X;
    for (std::size_t b = a + 1; b < byX.size(); ++b)
    {
      const Vec2& xb = walkers[stopped[byX[b]]].X;
      if (xb.x() - xa.x() > settings.MergeRadius)
      {
        break;
      }
      if ((xb - xa).norm() <= settings.MergeRadius)
      {
        const std::size_t ra = find(byX[a]), rb = find(byX[b]);
        // The smaller root wins so that clusters come out in seed order.
        parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }

  struct Cluster
  {
    std::vector<std::size_t> Members; // indices into walkers
    Vec2 Centre = Vec2::Zero();
    double MinPsi = 0.0;
    double BoundaryDistance = std::numeric_limits<double>::infinity();
  };
  std::vector<Cluster> clusters;
  {
    std::vector<int> clusterOfRoot(stopped.size(), -1);
    for (std::size_t a = 0; a < stopped.size(); ++a)
    {
      const std::size_t root = find(a);
      if (clusterOfRoot[root] < 0)
      {
        clusterOfRoot[root] = static_cast<int>(clusters.size());
        clusters.emplace_back();
      }
      clusters[clusterOfRoot[root]].Members.push_back(stopped[a]);
    }
  }
  std::vector<Cluster> zeros;
  for (Cluster& c : clusters)
  {
    std::size_t best = c.Members.front();
    for (std::size_t m : c.Members)
    {
      if (std::abs(walkers[m].Sample.Psi) < std::abs(walkers[best].Sample.Psi))
      {
        best = m;
      }
    }
    c.MinPsi = std::abs(walkers[best].Sample.Psi);
    // With noise, seeds stop anywhere in the region where |ψ| is below the
    // noise floor, and the smallest estimate is the luckiest, not the
    // closest: the coordinate-wise median of three or more stopping points
    // is a better centre. Without noise they coincide to MinStep anyway.
    c.Centre = walkers[best].X;
    if (c.Members.size() >= 3)
    {
      std::vector<double> xs, ys;
      for (std::size_t m : c.Members)
      {
        xs.push_back(walkers[m].X.x());
        ys.push_back(walkers[m].X.y());
      }
      c.Centre = Vec2(detail::Median(xs), detail::Median(ys));
    }
    // A lower bound of the boundary distance at the centre from the members'
    // distances (1-Lipschitz); unknown distances leave it unbounded.
    const auto boundaryBound = [&](const Vec2& centre) {
      double bound = -std::numeric_limits<double>::infinity();
      bool known = false;
      for (std::size_t m : c.Members)
      {
        const double d = walkers[m].Sample.BoundaryDistance;
        if (std::isfinite(d))
        {
          known = true;
          bound = std::max(bound, d - (centre - walkers[m].X).norm());
        }
      }
      return known ? bound : std::numeric_limits<double>::infinity();
    };
    c.BoundaryDistance = boundaryBound(c.Centre);
    if (!(c.BoundaryDistance > 0.0))
    {
      // The median of points of a non-convex domain may lie outside it.
      c.Centre = walkers[best].X;
      c.BoundaryDistance = boundaryBound(c.Centre);
    }
    zeros.push_back(std::move(c));
  }
  if (zeros.empty())
  {
    return result;
  }

  // Index circles, all in one call: IndexSamples points per zero, then its
  // centre (for |ψ| at the reported position).
  const int m = std::max(settings.IndexSamples, 3);
  std::vector<double> radii(zeros.size());
  points.clear();
  for (std::size_t a = 0; a < zeros.size(); ++a)
  {
    double radius = settings.IndexRadius;
    if (std::isfinite(zeros[a].BoundaryDistance))
    {
      radius = std::min(radius, settings.IndexBoundaryFraction * zeros[a].BoundaryDistance);
    }
    for (std::size_t b = 0; b < zeros.size(); ++b)
    {
      if (b != a)
      {
        radius = std::min(radius, 0.5 * (zeros[a].Centre - zeros[b].Centre).norm());
      }
    }
    radii[a] = radius;
    for (int j = 0; j < m; ++j)
    {
      const double phi = 2.0 * M_PI * j / m;
      points.push_back(zeros[a].Centre + radius * Vec2(std::cos(phi), std::sin(phi)));
    }
    points.push_back(zeros[a].Centre);
  }
  if (!detail::EvaluateBatch(evaluator, points, samples, stats.EvaluatorCalls, stats.EvaluatedPoints))
  {
    stats.Aborted = true;
    return result;
  }
  for (std::size_t a = 0; a < zeros.size(); ++a)
  {
    const std::size_t first = a * static_cast<std::size_t>(m + 1);
    std::complex<double> sum = 0.0;
    int count = 0;
    double phaseTurn = 0.0;
    double firstArg = 0.0, lastArg = 0.0;
    for (int j = 0; j < m; ++j)
    {
      const CrossFieldSample& s = samples[first + j];
      if (!detail::IsUsable(s) || !(std::abs(s.Psi) > 0.0))
      {
        continue;
      }
      const Vec2 offset = points[first + j] - zeros[a].Centre;
      const double r = offset.norm();
      const Vec2 u = Vec2(-offset.y(), offset.x()) / r;
      const std::complex<double> du(u.dot(s.GradRe), u.dot(s.GradIm));
      sum += std::complex<double>(0.0, -1.0) * r * du / s.Psi;
      const double angle = std::arg(s.Psi);
      if (count == 0)
      {
        firstArg = angle;
      }
      else
      {
        phaseTurn += detail::WrapAngle(angle - lastArg);
      }
      lastArg = angle;
      ++count;
    }
    if (2 * count < m)
    {
      ++stats.ClustersUnresolved;
      continue;
    }
    phaseTurn += detail::WrapAngle(firstArg - lastArg);
    const std::complex<double> mean = sum / static_cast<double>(count);
    Singularity singularity;
    singularity.Position = zeros[a].Centre;
    singularity.Index = static_cast<int>(std::lround(mean.real()));
    singularity.IndexResidual = mean.real() - singularity.Index;
    singularity.IndexImaginary = mean.imag();
    singularity.PhaseWinding = static_cast<int>(std::lround(phaseTurn / (2.0 * M_PI)));
    const CrossFieldSample& centre = samples[first + m];
    singularity.PsiMagnitude = detail::IsUsable(centre) ? std::abs(centre.Psi) : zeros[a].MinPsi;
    singularity.SeedCount = static_cast<int>(zeros[a].Members.size());
    singularity.Radius = radii[a];
    singularity.IndexSampleCount = count;
    if (singularity.Index == 0 && !settings.KeepZeroIndex)
    {
      ++stats.ClustersZeroIndex;
      continue;
    }
    result.push_back(singularity);
  }
  return result;
}

// Settings of TraceSeparatrices, in the problem's length units.
struct SeparatrixSettings
{
  // Angles sampled on the start circle to find the separatrix directions.
  int DirectionSamples = 64;
  // Radius of the start circle; 0 uses each singularity's index radius
  // (Singularity::Radius), already clamped away from the boundary and from
  // other singularities.
  double StartRadius = 0.0;
  // Step = StepFraction · min(boundary distance, distance to the nearest
  // singularity), clamped to [MinStep, MaxStep], and never more than half the
  // boundary distance. The cross field turns on the scale of the distance to
  // a singularity, so steps shrink near them.
  double StepFraction = 0.1;
  double MinStep = 1e-4;
  double MaxStep = 0.02;
  // A curve stops when its boundary distance falls below StopDistance, ...
  double StopDistance = 0.01;
  // ... when a step passes within CaptureRadius (at most half the target's
  // index radius) of a singularity, whose position then ends the curve, ...
  double CaptureRadius = 0.02;
  // ... after MaxSteps steps or MaxLength length, or when |ψ| falls below
  // NoiseFloor · sqrt(PsiVariance), where the cross is undefined: inside a
  // singularity's index circle this ends the curve at that singularity.
  int MaxSteps = 2000;
  double MaxLength = 10.0;
  double NoiseFloor = 3.0;
};

enum class SeparatrixStop
{
  Boundary,      // boundary distance below StopDistance
  Singularity,   // reached another singularity (Target)
  MaxSteps,
  MaxLength,
  InvalidSample, // the evaluator could not evaluate the next point
  ZeroPsi,       // |ψ| at the noise floor away from any singularity
  Aborted        // the evaluator failed
};

struct Separatrix
{
  std::vector<Vec2> Points; // starts at the source singularity
  int Source = -1;          // index into the singularities given
  int Target = -1;          // singularity that ended it, or −1
  SeparatrixStop Reason = SeparatrixStop::MaxSteps;
  double StartAngle = 0.0;  // θ of the start direction e^{iθ}
  double Length = 0.0;
};

struct SeparatrixStatistics
{
  std::size_t EvaluatorCalls = 0;
  std::size_t EvaluatedPoints = 0;
  int Steps = 0;        // integration steps (two calls each)
  bool Aborted = false; // the evaluator failed; curves end where they were
};

namespace detail
{
// Angles θ ∈ [0, 2π) where arg ψ(θ) − 4θ crosses a multiple of 2π, from
// samples of ψ at angles `theta` (increasing, in [0, 2π)). The function is
// unwrapped from the sample farthest from a crossing, so each crossing is
// one level of the unwrapped function; noise can make it cross a level
// several (an odd number of) times, and the middle crossing is kept. So the
// count is exactly |net winding of arg ψ − 4θ| = |n − 4|.
inline std::vector<double> SeparatrixAngles(
  const std::vector<double>& theta, const std::vector<std::complex<double>>& psi)
{
  const std::size_t k = theta.size();
  std::vector<double> result;
  if (k < 3)
  {
    return result;
  }
  std::vector<double> f(k);
  std::size_t start = 0;
  for (std::size_t j = 0; j < k; ++j)
  {
    f[j] = WrapAngle(std::arg(psi[j]) - 4.0 * theta[j]);
    if (std::abs(f[j]) > std::abs(f[start]))
    {
      start = j;
    }
  }
  // Unwrapped values g and angles t along the closed loop of k + 1 samples.
  std::vector<double> g(k + 1), t(k + 1);
  g[0] = f[start];
  t[0] = theta[start];
  for (std::size_t s = 1; s <= k; ++s)
  {
    const std::size_t previous = (start + s - 1) % k, current = (start + s) % k;
    g[s] = g[s - 1] + WrapAngle(f[current] - f[previous]);
    double step = theta[current] - theta[previous];
    if (step <= 0.0)
    {
      step += 2.0 * M_PI;
    }
    t[s] = t[s - 1] + step;
  }
  const double lo = std::min(g[0], g[k]), hi = std::max(g[0], g[k]);
  const long firstLevel = static_cast<long>(std::ceil(lo / (2.0 * M_PI)));
  const long lastLevel = static_cast<long>(std::floor(hi / (2.0 * M_PI)));
  for (long level = firstLevel; level <= lastLevel; ++level)
  {
    const double value = 2.0 * M_PI * static_cast<double>(level);
    if (!(value > lo && value < hi))
    {
      continue;
    }
    std::vector<double> crossings;
    for (std::size_t s = 0; s < k; ++s)
    {
      const double a = g[s] - value, b = g[s + 1] - value;
      if ((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0))
      {
        crossings.push_back(t[s] + (t[s + 1] - t[s]) * a / (a - b));
      }
    }
    if (crossings.empty())
    {
      continue;
    }
    double angle = std::fmod(crossings[crossings.size() / 2], 2.0 * M_PI);
    if (angle < 0.0)
    {
      angle += 2.0 * M_PI;
    }
    result.push_back(angle);
  }
  std::sort(result.begin(), result.end());
  return result;
}

// Distance from p to the segment [a, b].
inline double SegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b)
{
  const Vec2 ab = b - a;
  const double lengthSquare = ab.squaredNorm();
  double s = lengthSquare > 0.0 ? (p - a).dot(ab) / lengthSquare : 0.0;
  s = std::min(1.0, std::max(0.0, s));
  return (p - (a + s * ab)).norm();
}
} // namespace detail

// Separatrices of the singularities (as FindSingularities returns them):
// |4 − n| curves from each singularity of winding n ≠ 4. One evaluator call
// for all start circles, then two per step for all curves still moving.
inline std::vector<Separatrix> TraceSeparatrices(const CrossFieldEvaluator& evaluator,
  const std::vector<Singularity>& singularities, const SeparatrixSettings& settings = {},
  SeparatrixStatistics* statistics = nullptr)
{
  SeparatrixStatistics local;
  SeparatrixStatistics& stats = statistics ? *statistics : local;
  stats = SeparatrixStatistics{};
  std::vector<Separatrix> curves;
  if (!evaluator || singularities.empty())
  {
    return curves;
  }
  const auto startRadius = [&settings](const Singularity& s) {
    return settings.StartRadius > 0.0 ? settings.StartRadius : s.Radius;
  };

  // Start circles, one batch.
  const int k = std::max(settings.DirectionSamples, 8);
  std::vector<Vec2> points;
  std::vector<CrossFieldSample> samples;
  std::vector<std::size_t> traced;
  for (std::size_t i = 0; i < singularities.size(); ++i)
  {
    const double radius = startRadius(singularities[i]);
    if (singularities[i].Index == 4 || !(radius > 0.0))
    {
      continue;
    }
    traced.push_back(i);
    for (int j = 0; j < k; ++j)
    {
      const double theta = 2.0 * M_PI * j / k;
      points.push_back(singularities[i].Position + radius * Vec2(std::cos(theta), std::sin(theta)));
    }
  }
  if (traced.empty())
  {
    return curves;
  }
  if (!detail::EvaluateBatch(evaluator, points, samples, stats.EvaluatorCalls, stats.EvaluatedPoints))
  {
    stats.Aborted = true;
    return curves;
  }
  struct Tracer
  {
    Vec2 X = Vec2::Zero();
    Vec2 Tangent = Vec2::Zero();
    Vec2 Direction = Vec2::Zero(); // first-stage direction
    double Step = 0.0;
    bool Active = true;
    bool LeftSource = false; // self-capture only after leaving the source
  };
  std::vector<Tracer> tracers;
  for (std::size_t a = 0; a < traced.size(); ++a)
  {
    const Singularity& s = singularities[traced[a]];
    std::vector<double> theta;
    std::vector<std::complex<double>> psi;
    for (int j = 0; j < k; ++j)
    {
      const CrossFieldSample& sample = samples[a * k + j];
      if (detail::IsUsable(sample) && std::abs(sample.Psi) > 0.0)
      {
        theta.push_back(2.0 * M_PI * j / k);
        psi.push_back(sample.Psi);
      }
    }
    // With most of the circle missing the winding of arg ψ − 4θ is unknown.
    if (2 * theta.size() < static_cast<std::size_t>(k))
    {
      continue;
    }
    const double radius = startRadius(s);
    for (double angle : detail::SeparatrixAngles(theta, psi))
    {
      const Vec2 direction(std::cos(angle), std::sin(angle));
      Separatrix curve;
      curve.Source = static_cast<int>(traced[a]);
      curve.StartAngle = angle;
      curve.Points = { s.Position, s.Position + radius * direction };
      curve.Length = radius;
      curves.push_back(std::move(curve));
      Tracer tracer;
      tracer.X = curves.back().Points.back();
      tracer.Tangent = direction;
      tracers.push_back(tracer);
    }
  }

  const auto captureRadius = [&settings](const Singularity& s) {
    return s.Radius > 0.0 ? std::min(settings.CaptureRadius, 0.5 * s.Radius) : settings.CaptureRadius;
  };
  const auto stop = [&](std::size_t c, SeparatrixStop reason) {
    curves[c].Reason = reason;
    tracers[c].Active = false;
  };
  // One batch evaluation for the tracers `ids` at `at`; on failure (an
  // abort) they all stop and the tracing ends.
  const auto evaluateOrStop = [&](const std::vector<Vec2>& at, const std::vector<std::size_t>& ids) {
    if (detail::EvaluateBatch(evaluator, at, samples, stats.EvaluatorCalls, stats.EvaluatedPoints))
    {
      return true;
    }
    stats.Aborted = true;
    for (std::size_t c : ids)
    {
      stop(c, SeparatrixStop::Aborted);
    }
    return false;
  };
  std::vector<std::size_t> owners;
  for (int step = 0;; ++step)
  {
    // Stage 1 at the current points: stopping tests, step size, direction.
    points.clear();
    owners.clear();
    for (std::size_t c = 0; c < curves.size(); ++c)
    {
      if (tracers[c].Active)
      {
        points.push_back(tracers[c].X);
        owners.push_back(c);
      }
    }
    if (points.empty())
    {
      break;
    }
    if (!evaluateOrStop(points, owners))
    {
      break;
    }
    std::vector<std::size_t> moving;
    std::vector<Vec2> from, first;
    std::vector<double> steps;
    for (std::size_t q = 0; q < owners.size(); ++q)
    {
      const std::size_t c = owners[q];
      Tracer& tracer = tracers[c];
      Separatrix& curve = curves[c];
      const CrossFieldSample& s = samples[q];
      if (!detail::IsUsable(s))
      {
        // The point is outside or unknown: end at the last good point.
        if (curve.Points.size() > 2)
        {
          curve.Length -= (curve.Points.back() - curve.Points[curve.Points.size() - 2]).norm();
          curve.Points.pop_back();
        }
        stop(c, SeparatrixStop::InvalidSample);
        continue;
      }
      const double boundary = s.BoundaryDistance;
      if (boundary < settings.StopDistance)
      {
        stop(c, SeparatrixStop::Boundary);
        continue;
      }
      if (!(std::abs(s.Psi) > detail::NoiseFloor(s, settings.NoiseFloor)) ||
        !AlignedCrossDirection(s.Psi, tracer.Tangent, tracer.Direction))
      {
        // With noise, the region where |ψ| is below the noise floor can be
        // wider than the capture radius: a curve that loses its direction
        // inside a singularity's index circle has reached that singularity.
        int target = -1;
        double closest = std::numeric_limits<double>::infinity();
        for (std::size_t o = 0; o < singularities.size(); ++o)
        {
          const double d = (singularities[o].Position - tracer.X).norm();
          if ((static_cast<int>(o) != curve.Source || tracer.LeftSource) &&
            d < singularities[o].Radius && d < closest)
          {
            closest = d;
            target = static_cast<int>(o);
          }
        }
        if (target >= 0)
        {
          curve.Length += closest;
          curve.Points.push_back(singularities[target].Position);
          curve.Target = target;
          stop(c, SeparatrixStop::Singularity);
        }
        else
        {
          stop(c, SeparatrixStop::ZeroPsi);
        }
        continue;
      }
      if (step >= settings.MaxSteps)
      {
        stop(c, SeparatrixStop::MaxSteps);
        continue;
      }
      if (curve.Length >= settings.MaxLength)
      {
        stop(c, SeparatrixStop::MaxLength);
        continue;
      }
      double nearest = std::numeric_limits<double>::infinity();
      for (const Singularity& other : singularities)
      {
        nearest = std::min(nearest, (other.Position - tracer.X).norm());
      }
      double h = settings.StepFraction * nearest;
      if (std::isfinite(boundary))
      {
        h = std::min(h, settings.StepFraction * boundary);
      }
      h = std::min(std::max(h, settings.MinStep), settings.MaxStep);
      if (std::isfinite(boundary))
      {
        h = std::min(h, 0.5 * boundary);
      }
      tracer.Step = h;
      moving.push_back(c);
      from.push_back(tracer.X);
      first.push_back(tracer.Direction);
      steps.push_back(h);
    }
    if (moving.empty())
    {
      continue;
    }
    // Heun's second stage at the Euler points, in one batch
    // (LockstepStreamlines.h). Following the cross nearest to the first
    // stage keeps both stages on the same branch; an unusable second stage
    // falls back to Euler.
    const auto crossDirections = [&](int, const std::vector<Vec2>& at,
                                   const std::vector<Vec2>& previous,
                                   std::vector<Vec2>& directions, std::vector<char>& defined) {
      if (!evaluateOrStop(at, moving))
      {
        return false;
      }
      for (std::size_t q = 0; q < moving.size(); ++q)
      {
        defined[q] = detail::IsUsable(samples[q]) &&
          AlignedCrossDirection(samples[q].Psi, previous[q], directions[q]);
      }
      return true;
    };
    std::vector<Vec2> combined;
    if (!LockstepStepDirections<Vec2, 2>(
          StreamIntegrator::Heun, from, steps, first, crossDirections, combined))
    {
      break;
    }
    ++stats.Steps;
    for (std::size_t q = 0; q < moving.size(); ++q)
    {
      const std::size_t c = moving[q];
      Tracer& tracer = tracers[c];
      Separatrix& curve = curves[c];
      const Vec2 direction = combined[q];
      const Vec2 next = tracer.X + tracer.Step * direction;
      const Singularity& source = singularities[curve.Source];
      int target = -1;
      double closest = std::numeric_limits<double>::infinity();
      for (std::size_t o = 0; o < singularities.size(); ++o)
      {
        if (static_cast<int>(o) == curve.Source && !tracer.LeftSource)
        {
          continue;
        }
        const double d = detail::SegmentDistance(singularities[o].Position, tracer.X, next);
        if (d < captureRadius(singularities[o]) && d < closest)
        {
          closest = d;
          target = static_cast<int>(o);
        }
      }
      if (target >= 0)
      {
        const Vec2& end = singularities[target].Position;
        curve.Length += (end - tracer.X).norm();
        curve.Points.push_back(end);
        curve.Target = target;
        stop(c, SeparatrixStop::Singularity);
        continue;
      }
      curve.Length += (next - tracer.X).norm();
      curve.Points.push_back(next);
      tracer.Tangent = direction.normalized();
      tracer.X = next;
      if ((next - source.Position).norm() > 2.0 * captureRadius(source) + startRadius(source))
      {
        tracer.LeftSource = true;
      }
    }
  }
  return curves;
}
} // namespace gridfree

#endif
