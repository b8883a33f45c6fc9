// Source terms f of Δu − c·u = f and the one-step estimate of their
// contribution ∫_B f(y) G(x, y) dy over a walk's ball (paper Sec. 2.3, 2.4
// and 4.2; FORMULAS.md §2, §3 and §6 for signs, weights and samplers).
//
// f is the sum of
// - a volume source (a sampled dataset or an expression), evaluated through a
//   per-thread VolumeSource object, with the sampling strategies of paper
//   Sec. 4.2.1 / Fig. 7: uniform in the ball, proportional to G, or both
//   combined by the balance heuristic (multiple importance sampling);
// - point sources s·δ_z, each adding s·G(x, z) when z lies in the ball
//   (Sec. 4.2.2: the ball's share of a delta is sampled exactly);
// - curve sources s·δ_γ, adding s(z)·G(x, z)/p(z) for one point z drawn on
//   the part of γ inside the ball with density p ∝ 1/|z − x| (Sec. 4.2.2's
//   importance sampling, with G's pole cancelled in 3D).
#ifndef GRIDFREE_SOURCES_SOURCE_TERMS_H
#define GRIDFREE_SOURCES_SOURCE_TERMS_H

#include <gridfree/sources/SourceSampling.h>
#include <gridfree/sampling/BallSampling.h>
#include <gridfree/sources/ConcentratedSources.h>
#include <gridfree/sources/SourceDensityMap.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace gridfree
{
// A volume source f(y) with a fixed number of components. Evaluate may use
// scratch memory, so every thread owns its own object.
template <int DIM>
class VolumeSource
{
public:
  virtual ~VolumeSource() = default;
  // Writes f(y), Components() numbers, into f.
  virtual void Evaluate(const Vec<DIM>& y, double* f) = 0;
  // The box outside which f vanishes; false when f has unbounded support.
  virtual bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const = 0;

  // The range [lowest, highest] of component c of f everywhere (0 included
  // where f vanishes outside its data); false when it is not known. It
  // bounds what one screened walk can gather from the source, which the
  // error-bar rule uses (Problem.h, ErrorBarReliability.h). Sources that
  // cannot prove a range keep this default.
  virtual bool ValueBounds(int /*c*/, double& /*lowest*/, double& /*highest*/) const
  {
    return false;
  }

  // Writes f(y) (components numbers) and ∇f(y) (components × DIM numbers,
  // gradient[c·DIM + i] = ∂f_c/∂y_i). The Hessian's source term needs ∇f
  // (paper Sec. 3.3, integration-by-parts form). This default differentiates
  // Evaluate by central differences with step DifferenceStep (relative to
  // max(1, |y|∞) when no step was set); sources that know their derivative
  // exactly (interpolated data) override it.
  virtual void EvaluateGradient(const Vec<DIM>& y, int components, double* f, double* gradient)
  {
    const double scale = std::max(1.0, y.cwiseAbs().maxCoeff());
    const double h = this->DifferenceStep > 0.0 ? this->DifferenceStep : 1e-5 * scale;
    // Thread-local scratch: a stateless source may be shared by threads.
    thread_local std::vector<double> scratch;
    scratch.resize(2 * static_cast<std::size_t>(components));
    double* plus = scratch.data();
    double* minus = plus + components;
    this->Evaluate(y, f);
    for (int i = 0; i < DIM; ++i)
    {
      Vec<DIM> step = Vec<DIM>::Zero();
      step[i] = h;
      this->Evaluate(y + step, plus);
      this->Evaluate(y - step, minus);
      for (int c = 0; c < components; ++c)
      {
        gradient[c * DIM + i] = (plus[c] - minus[c]) / (2.0 * h);
      }
    }
  }

  // Step of the default EvaluateGradient; 0 chooses 1e-5·max(1, |y|∞).
  void SetDifferenceStep(double h) { this->DifferenceStep = h; }

private:
  double DifferenceStep = 0.0;
};

// The range of component c of values stored `components` per point, with 0
// (the value outside the data): what an interpolation with non-negative
// weights that sum to at most 1 can give. NaN when a value is not finite
// (std::min would skip a NaN, and the range would claim a bound it lacks).
inline void StoredValueRange(
  const std::vector<float>& values, int components, int c, double& lowest, double& highest)
{
  lowest = 0.0;
  highest = 0.0;
  for (std::size_t k = static_cast<std::size_t>(c); k < values.size();
       k += static_cast<std::size_t>(components))
  {
    const double v = static_cast<double>(values[k]);
    if (!std::isfinite(v))
    {
      lowest = highest = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    lowest = std::min(lowest, v);
    highest = std::max(highest, v);
  }
}

// The concentrated sources, shared read-only by all threads.
template <int DIM>
struct ConcentratedSourceSet
{
  const PointSources<DIM>* Points = nullptr;
  const CurveSources<DIM>* Curves = nullptr;
  // Not a concentrated source: the volume source's density map that
  // SourceSampling::SourceDensity draws from (built once by the problem,
  // shared read-only); null or empty makes it Green's-function sampling.
  const SourceDensityMap<DIM>* VolumeDensity = nullptr;

  bool Empty() const
  {
    return (!this->Points || this->Points->Empty()) && (!this->Curves || this->Curves->Empty());
  }
};

// One thread's evaluator of the source contribution over a ball.
template <int DIM>
class SourceIntegrator
{
public:
  SourceIntegrator(int components, SourceSampling sampling, VolumeSource<DIM>* volume,
    const ConcentratedSourceSet<DIM>& concentrated)
    : Components(components)
    , Sampling(sampling)
    , Volume(volume)
    , Concentrated(concentrated)
    , F(components)
    , Strength(components)
  {
  }

  bool Active() const { return this->Volume || !this->Concentrated.Empty(); }

  // Under source-density sampling, the largest ball radius for a walker at
  // x: R² ≤ 2n·T / F(x), F(x) the map's |f| in x's cell, so that no sample
  // of the ball's source term, at most F·∫G = F·R²/(2n), exceeds about
  // T = kSourceStepShare · M·Φ, M the map's mass and Φ the harmonic
  // Green's function's scale over the domain (1/(4π · half the diagonal)
  // in 3D, 1/(2π) in 2D). Why: a walker standing inside a narrow source
  // with a ball much larger than it (the source far from the boundary)
  // had its map sample fall a few thousandths from it, where G ~ 1/(4πr),
  // and the balance heuristic weighs that sample by about M·G(r): one
  // sample tens of standard deviations from the mean, a walk a few hundred
  // walks see once, and the error-bar rule flagged 5% of such points (3D
  // bump of width 0.05 in a unit sphere, 256 walks) whose bars were right.
  // With the cap, 0.75% (Documentation/ErrorBars.md). Any ball inside the
  // domain gives an unbiased step; this one only costs a few more steps
  // where |f| is large. +inf otherwise.
  static constexpr double kSourceStepShare = 2.0;
  double SourceStepCap(const Vec<DIM>& x, double diagonal) const
  {
    const SourceDensityMap<DIM>* map = this->Concentrated.VolumeDensity;
    if (this->Sampling != SourceSampling::SourceDensity || !this->Volume || !map || map->Empty())
    {
      return std::numeric_limits<double>::infinity();
    }
    const double local = map->Pdf(x) * map->MassSum();
    if (!(local > 0.0))
    {
      return std::numeric_limits<double>::infinity();
    }
    const double scale = DIM == 3 ? 1.0 / (4.0 * M_PI * 0.5 * diagonal) : 1.0 / (2.0 * M_PI);
    return std::sqrt(2.0 * DIM * kSourceStepShare * map->MassSum() * scale / local);
  }

  // Adds an unbiased one-sample estimate of ∫_{B(x,R)} f(y) G(x, y) dy to
  // integral (Components() numbers). `green` is the ball's Green's function
  // object (harmonic or Yukawa; see GreensFunctions.h).
  template <class Green>
  void Accumulate(const Vec<DIM>& x, const Green& green, RandomStream& rng, double* integral)
  {
    this->Accumulate(x, green, rng, integral, [](const Vec<DIM>&) { return 1.0; });
  }

  // The same over part of the ball: each sample y is multiplied by keep(y),
  // called only for samples of nonzero weight. Walk on stars passes the
  // indicator of its star-shaped region (y seen from x), times 1/α.
  template <class Green, class Keep>
  void Accumulate(
    const Vec<DIM>& x, const Green& green, RandomStream& rng, double* integral, const Keep& keep)
  {
    const double radius = green.Radius();
    if (this->Volume)
    {
      const double volume = UnitBallVolume<DIM>() * PowerOf<DIM>(radius);
      switch (this->Sampling)
      {
        case SourceSampling::Uniform:
        {
          const Vec<DIM> d = radius * SampleUnitBall<DIM>(rng);
          this->AddVolumeSample(x + d, volume * green.Value(d.norm()), integral, keep);
          break;
        }
        case SourceSampling::GreensFunction:
        case SourceSampling::Automatic: // (undecided: Problem resolves it)
        {
          const Vec<DIM> d = green.SampleOffset(rng);
          this->AddVolumeSample(x + d, green.Integral(), integral, keep);
          break;
        }
        case SourceSampling::MultipleImportance:
        {
          // Balance heuristic with one sample per strategy: each sample y
          // weighs f(y) G / (p_U + p_G) = f(y) / (1/(|B| G) + 1/∫G), a form
          // that stays finite where G is infinite (y = x).
          const double integralG = green.Integral();
          const Vec<DIM> du = radius * SampleUnitBall<DIM>(rng);
          this->AddVolumeSample(x + du,
            1.0 / (1.0 / (volume * green.Value(du.norm())) + 1.0 / integralG), integral, keep);
          const Vec<DIM> dg = green.SampleOffset(rng);
          this->AddVolumeSample(x + dg,
            1.0 / (1.0 / (volume * green.Value(dg.norm())) + 1.0 / integralG), integral, keep);
          break;
        }
        case SourceSampling::SourceDensity:
        {
          // Balance heuristic with one sample per strategy: each sample y
          // in the ball weighs f(y) G / (p_G + p_S), p_G = G / ∫G and p_S
          // the map's density, i.e. f(y) / (1/∫G + p_S/G): ∫G where G is
          // infinite (y = x), 0 where G vanishes (on the sphere). p_G
          // covers the whole ball, so the estimate is unbiased whatever the
          // map; the map's sample finds a narrow source whenever the ball
          // holds it. The map draws its DIM + 2 numbers whether or not its
          // point falls in the ball, so walks stay reproducible.
          const double integralG = green.Integral();
          const SourceDensityMap<DIM>* map = this->Concentrated.VolumeDensity;
          const bool mapped = map && !map->Empty();
          const Vec<DIM> dg = green.SampleOffset(rng);
          const double gg = green.Value(dg.norm());
          const double pg = mapped ? map->Pdf(x + dg) : 0.0;
          this->AddVolumeSample(x + dg, 1.0 / (1.0 / integralG + pg / gg), integral, keep);
          if (mapped)
          {
            const Vec<DIM> y = map->Sample(rng);
            const double r = (y - x).norm();
            if (r < radius)
            {
              const double gs = green.Value(r);
              this->AddVolumeSample(y, gs / (gs / integralG + map->Pdf(y)), integral, keep);
            }
          }
          break;
        }
      }
    }
    const int nc = this->Components;
    if (this->Concentrated.Points && !this->Concentrated.Points->Empty())
    {
      this->Concentrated.Points->ForEachInBall(x, radius, [&](const Vec<DIM>& z, const double* s) {
        double g = green.Value((z - x).norm());
        if (g > 0.0)
        {
          g *= keep(z);
        }
        for (int c = 0; c < nc; ++c)
        {
          integral[c] += g * s[c];
        }
      });
    }
    if (this->Concentrated.Curves && !this->Concentrated.Curves->Empty())
    {
      Vec<DIM> z;
      double inverseDensity = 0.0;
      if (this->Concentrated.Curves->SampleInBall(
            x, radius, rng, this->CurveScratch, z, this->Strength.data(), inverseDensity))
      {
        double g = inverseDensity * green.Value((z - x).norm());
        if (g > 0.0)
        {
          g *= keep(z);
        }
        for (int c = 0; c < nc; ++c)
        {
          integral[c] += g * this->Strength[c];
        }
      }
    }
  }

private:
  template <class Keep>
  void AddVolumeSample(const Vec<DIM>& y, double weight, double* integral, const Keep& keep)
  {
    if (!(weight > 0.0) || !std::isfinite(weight))
    {
      return; // G = 0 on the sphere; a zero-weight sample adds nothing
    }
    weight *= keep(y);
    if (weight == 0.0)
    {
      return;
    }
    this->Volume->Evaluate(y, this->F.data());
    for (int c = 0; c < this->Components; ++c)
    {
      integral[c] += weight * this->F[c];
    }
  }

  int Components;
  SourceSampling Sampling;
  VolumeSource<DIM>* Volume;
  ConcentratedSourceSet<DIM> Concentrated;
  typename CurveSources<DIM>::Scratch CurveScratch;
  std::vector<double> F;
  std::vector<double> Strength;
};
} // namespace gridfree

#endif
