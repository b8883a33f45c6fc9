// Steps toward a narrow peak of the boundary data (WalkSettings::PeakSteps).
//
// Why: where the data has a narrow peak (a small hot spot, or the potential
// of a charge just outside the boundary), much of u far from the peak
// comes from the few walks that end on it. Uniform steps bring a point
// only a handful of them in a few hundred walks, often none, and the
// sample variance misses them: on an ellipsoid with the Yukawa potential
// of a pole 0.05 outside its tip (c = 6.25), 300 points at 256 walks had
// mean z² 2.9, every large |z| an estimate below the exact value.
//
// The step draws its landing point y on ∂B(x, R) from the defensive mixture
//   q(y) = (1 − α)·U + α·Σ_j w_j·V_j(y),   V_j(y) ∝ e^{−√c·s_j}/s_j,
// s_j = |y − p_j|, p_j the peaks (the centroid of the primitive with the
// largest |g|, or another geometry's sampled boundary point with it, and up
// to three more at least a quarter as high elsewhere),
// w_j their shares by height, U the uniform density, and multiplies the
// walk's weight by U/q(y) ≤ 1/(1 − α)
// (the exact importance weight: E_q[(U/q)·u] = mean over ∂B of u). V is
// the step's zero-variance density when u is the potential of a charge at
// p_j, e^{−√c s}/s (1/s for c = 0), whatever the screening. On the sphere of
// radius R about x, at d = |x − p| ≥ R from a peak p (p lies on the boundary and
// R is at most x's distance to it), the area element is (2πR/d)·s ds, so s
// has density ∝ e^{−√c s} on [d − R, d + R] (uniform for c = 0), drawn by
// inverting its distribution, the azimuth uniform, and
//   V/U = 2Rd√c·e^{−√c (s − d + R)} / (s·(1 − e^{−2√c R}))   (d/s at c = 0).
// Far from the peaks (d ≫ R) V/U ≈ 1 and the step is nearly uniform; near
// one the landing points gather toward it. Any peaks keep the walk
// unbiased; a poor choice costs variance only, and leaving out a peak that
// matters makes the walks reach it more rarely than uniform ones.
//
// In 2D, V_j ∝ K0(√c s_j), the 2D charge's potential, over the circle of
// radius R about x. Its mean over that circle is I0(√c R)·K0(√c d) (Graf's
// addition theorem, for d > R), so
//   V/U = K0(√c s) / (I0(√c R)·K0(√c d))
// exactly, and V is drawn by rejection from uniform angles: V/U falls
// with s, so its largest value is at s = d − R, and a uniform angle is
// kept with probability (V/U)(s) / (V/U)(d − R), after about (V/U)(d − R)
// tries (which grows only as −log(d − R) near the peak; beyond
// kMostTries the step is uniform, a choice fixed by x and R, so that
// every step's density stays known). The screened equation only: the
// Laplace equation's 2D charge, −log s, changes sign. On the unit circle
// with K0(2.5 s) data of a pole 0.055 outside it, 300 points at 256 walks,
// uniform steps flagged 72–76 points rightly (mean z² 1.54–2.25); these
// flag none, with mean z² 0.92–1.10 and a quarter of the error, at 1.7
// times the time (ErrorBars.md). A Poisson kernel toward the peak, drawn
// without rejection, leaned as 1/s² and missed points.
//
// The weights vary with the path, so data with a large constant part gain
// variance from them: Automatic guides only where the peak stands out
// (the largest |g| at least kStandsOut times the area-weighted mean |g|).
#ifndef GRIDFREE_ESTIMATORS_PEAK_GUIDE_H
#define GRIDFREE_ESTIMATORS_PEAK_GUIDE_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
template <int DIM>
class PeakGuide
{
public:
  // The mixture's share α of landing points drawn toward the peak. On the
  // ellipsoid's Coulomb peak at 256 walks, the RMS error over 300 points
  // was 0.041 with uniform steps, 0.011 with α = 0.5, 0.0064 with 0.7 and
  // 0.0044 with 0.8; with a constant 1 added to the data (a twentieth of
  // the peak), 0.0057, 0.0091 and 0.014: the weights' spread then costs
  // more. At 0.5, 9 of 300 points of a bumpy blob were flagged (their
  // error bars right), 2 at 0.7.
  static constexpr double Share = 0.7;
  // How far the largest |g| must stand above the area-weighted mean |g|
  // for Automatic to guide.
  static constexpr double kStandsOut = 10.0;

  // At most this many peaks share the mixture. A further peak is taken
  // where the data rise again to a quarter of the first peak's height,
  // beyond the peaks found so far (each covers 4 times the distance at
  // which its data fall to half: a charge's own shoulder there is a
  // seventh of its height). With two poles and the steps leaning toward
  // one only, the walks reached the other even more rarely than uniform
  // ones: mean z² 3.27 and 8 misses of 300 against 1.79 and 1 with
  // uniform steps.
  static constexpr int kMostPeaks = 4;
  // A 2D step whose rejection would need more tries than this on average
  // is uniform (it takes a ball whose sphere all but touches a peak: the
  // tries grow only as −log(d − R)).
  static constexpr double kMostTries = 64.0;

  /// The peaks of the boundary's data (at a mesh's primitives' centroids or
  /// another geometry's sampled points, the largest |g| over the components
  /// there) and how far the first stands out; Found() is false where every
  /// value is 0, and for the 2D Laplace and Poisson equations.
  PeakGuide(const Boundary<DIM>& boundary, double c)
    : SqrtC(std::sqrt(std::max(c, 0.0)))
  {
    if (DIM == 2 && !(c > 0.0))
    {
      return;
    }
    // A mesh's primitives' centroids, each weighed by its size, or another
    // geometry's sampled points (Boundary::GeometrySamples), weighed alike:
    // the lattice's band holds about as many of them per unit of area
    // whatever the boundary's slope.
    const auto& vertices = boundary.MeshVertices();
    const auto& primitives = boundary.MeshPrimitives();
    const auto& samples = boundary.GeometrySamples();
    const std::size_t n = boundary.IsMesh() ? primitives.size() : samples.size();
    std::vector<double> value(static_cast<std::size_t>(std::max(1, boundary.Components())));
    std::vector<Vec<DIM>> centroid(n);
    std::vector<double> height(n, 0.0);
    double weighted = 0.0, area = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      ClosestPointResult<DIM> hit;
      double size = 1.0;
      if (boundary.IsMesh())
      {
        hit = boundary.PrimitiveCentroid(i);
        size = PrimitiveSize(vertices, primitives[i]);
      }
      else
      {
        hit = samples[i];
      }
      boundary.Evaluate(hit, value.data());
      double here = 0.0;
      for (double v : value)
      {
        here = std::max(here, std::abs(v));
      }
      centroid[i] = hit.point;
      if (!std::isfinite(here))
      {
        continue;
      }
      height[i] = here;
      weighted += size * here;
      area += size;
    }
    const double mean = area > 0.0 ? weighted / area : 0.0;
    // Greedy: the highest primitive not covered by a peak found so far.
    std::vector<double> reach; // each peak's covered distance
    double total = 0.0;
    while (static_cast<int>(this->Peaks.size()) < kMostPeaks)
    {
      std::size_t best = n;
      for (std::size_t i = 0; i < n; ++i)
      {
        bool covered = false;
        for (std::size_t j = 0; j < this->Peaks.size() && !covered; ++j)
        {
          covered = (centroid[i] - this->Peaks[j]).norm() <= reach[j];
        }
        if (!covered && height[i] > 0.0 && (best == n || height[i] > height[best]))
        {
          best = i;
        }
      }
      if (best == n ||
        (!this->Peaks.empty() && height[best] < 0.25 * this->Height.front()))
      {
        break;
      }
      // Where the data first fall to half the peak's height.
      double half = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < n; ++i)
      {
        if (height[i] < 0.5 * height[best])
        {
          half = std::min(half, (centroid[i] - centroid[best]).norm());
        }
      }
      this->Peaks.push_back(centroid[best]);
      this->Height.push_back(height[best]);
      reach.push_back(4.0 * half);
      total += height[best];
    }
    for (double& h : this->Height)
    {
      h /= total; // the peaks' shares of the guided landing points
    }
    this->Prominence = !this->Peaks.empty() && mean > 0.0 ? height[this->FirstIndex(height)] / mean : 0.0;
  }

  bool Found() const { return !this->Peaks.empty(); }
  /// The peaks, highest first.
  const std::vector<Vec<DIM>>& PeakPoints() const { return this->Peaks; }
  const Vec<DIM>& PeakPoint() const { return this->Peaks.front(); }
  /// The largest |g| over the area-weighted mean |g|.
  double StandsOut() const { return this->Prominence; }

  /// The most a step's factor can be: 1/(1 − α).
  static double LargestFactor() { return 1.0 / (1.0 - Share); }

  /// A step of radius R from x: its unit direction, and the factor U/q
  /// its weight takes, q = (1 − α)·U + α·Σ_j w_j·V_j (w_j the peaks' shares,
  /// by height).
  Vec<DIM> Step(const Vec<DIM>& x, double radius, RandomStream& rng, double& factor) const
  {
    // (R ≤ d always for a ball inside the boundary; a relaxed step that is
    // not, or a walker on a peak, steps uniformly with factor 1.)
    for (const Vec<DIM>& p : this->Peaks)
    {
      const double d = (p - x).norm();
      if (!(d > radius) || !(radius > 0.0) ||
        (DIM == 2 && !(this->DensityOverUniform(d, radius, d - radius) <= kMostTries)))
      {
        factor = 1.0;
        return SampleUnitSphere<DIM>(rng);
      }
    }
    Vec<DIM> omega;
    if (rng.NextDouble() < Share)
    {
      std::size_t j = 0;
      if (this->Peaks.size() > 1)
      {
        double pick = rng.NextDouble();
        while (j + 1 < this->Peaks.size() && pick >= this->Height[j])
        {
          pick -= this->Height[j];
          ++j;
        }
      }
      const Vec<DIM> toPeak = this->Peaks[j] - x;
      const double d = toPeak.norm();
      if constexpr (DIM == 2)
      {
        // By rejection from uniform angles (the header's 2D density).
        const double top = this->DensityOverUniform(d, radius, d - radius);
        do
        {
          omega = SampleUnitSphere<DIM>(rng);
        } while (rng.NextDouble() * top >
          this->DensityOverUniform(d, radius, (x + radius * omega - this->Peaks[j]).norm()));
      }
      else
      {
        const Vec<DIM> e = toPeak / d;
        const double s = this->SampleDistance(d, radius, rng.NextDouble());
        const double cosine =
          std::clamp((radius * radius + d * d - s * s) / (2.0 * radius * d), -1.0, 1.0);
        const double sine = std::sqrt(std::max(0.0, 1.0 - cosine * cosine));
        const double phi = 2.0 * M_PI * rng.NextDouble();
        const Vec<DIM> t1 = e.unitOrthogonal();
        const Vec<DIM> t2 = e.cross(t1);
        omega = cosine * e + sine * (std::cos(phi) * t1 + std::sin(phi) * t2);
      }
    }
    else
    {
      omega = SampleUnitSphere<DIM>(rng);
    }
    const Vec<DIM> y = x + radius * omega;
    double guided = 0.0;
    for (std::size_t j = 0; j < this->Peaks.size(); ++j)
    {
      guided += this->Height[j] *
        this->DensityOverUniform((this->Peaks[j] - x).norm(), radius, (y - this->Peaks[j]).norm());
    }
    factor = 1.0 / ((1.0 - Share) + Share * guided);
    return omega;
  }

  /// V/U at a landing point s from a peak (a sphere of radius R at d).
  double DensityOverUniform(double d, double radius, double s) const
  {
    const double span = 2.0 * radius * this->SqrtC;
    if (!(s > 0.0))
    {
      return std::numeric_limits<double>::infinity();
    }
    if constexpr (DIM == 2)
    {
      // K0(ks)/(I0(kR)·K0(kd)), from the scaled functions (no overflow).
      const double k = this->SqrtC;
      return BesselK0Scaled(k * s) / (BesselI0Scaled(k * radius) * BesselK0Scaled(k * d)) *
        std::exp(k * (d - s - radius));
    }
    if (span < 1e-8)
    {
      return d / s;
    }
    return 2.0 * radius * d * this->SqrtC * std::exp(-this->SqrtC * (s - (d - radius))) /
      (s * -std::expm1(-span));
  }

private:
  // s on [d − R, d + R] with density ∝ e^{−√c s}, from a uniform u.
  double SampleDistance(double d, double radius, double u) const
  {
    const double near = d - radius;
    const double span = 2.0 * radius * this->SqrtC;
    if (span < 1e-8)
    {
      return near + 2.0 * radius * u;
    }
    return std::min(d + radius, near - std::log1p(u * std::expm1(-span)) / this->SqrtC);
  }

  // A primitive's area (3D) or length (2D), which weighs its |g| in the
  // mean.
  template <class Vertices, class Primitive>
  static double PrimitiveSize(const Vertices& vertices, const Primitive& p)
  {
    const Vec<DIM> a = vertices[static_cast<std::size_t>(p[0])];
    const Vec<DIM> b = vertices[static_cast<std::size_t>(p[1])];
    if constexpr (DIM == 2)
    {
      return (b - a).norm();
    }
    else
    {
      const Vec<DIM> c = vertices[static_cast<std::size_t>(p[2])];
      return 0.5 * (b - a).cross(c - a).norm();
    }
  }

  static std::size_t FirstIndex(const std::vector<double>& height)
  {
    return static_cast<std::size_t>(
      std::max_element(height.begin(), height.end()) - height.begin());
  }

  double SqrtC;
  std::vector<Vec<DIM>> Peaks;
  std::vector<double> Height; // after construction: each peak's share
  double Prominence = 0.0;
};
} // namespace gridfree

#endif
