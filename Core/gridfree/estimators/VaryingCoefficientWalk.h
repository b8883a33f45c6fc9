// Walk on spheres with delta tracking for the equation with spatially
// varying coefficients (VaryingCoefficients.h; Sawhney, Seyb, Jarosz and
// Crane, SIGGRAPH 2022, Secs. 4–5):
//
//   ∇·(α∇u) − σu = f in Ω,  u = g on ∂Ω   ⇔   ΔU − σ′U = f′,  U = √α u.
//
// On a ball B(x, R) inside Ω, with a constant σ̄ ≥ 0 from the majorant
// (ScreeningMajorant.h), U solves the screened equation ΔU − σ̄U = F with
// F = f′ − (σ̄ − σ′)U, so by the screened mean-value identity (FORMULAS.md §3,
// the walk's Eqn. 9 with the sign of §2)
//
//   U(x) = C·mean_∂B U − ∫_B G_σ̄ f′ + ∫_B G_σ̄ (σ̄ − σ′) U,
//
// with C = 1 − σ̄∫G_σ̄ the Yukawa boundary weight. With a floor σ_c ≤ σ′ on
// the ball (decomposition tracking) the walk's weight is multiplied by
// keep = 1 − σ_c∫G_σ̄ on every step; it picks the sphere with probability
// C/keep (and moves to a uniform point on it), otherwise it "collides" at
// y ~ G_σ̄/∫G_σ̄ and continues from y with its weight also multiplied by
// (σ̄ − σ′(y))/(σ̄ − σ_c) (1 for a null collision with σ_c = σ′ = 0; 0 for an
// absorption, σ′ = σ̄). Weights rather than analog absorption: killing walks
// with probability σ′/σ̄ turned a smooth decay into all-or-nothing values,
// several times the variance on absorbing tissue. Walks whose weight falls
// below 0.1 play Russian roulette. Every step subtracts weight·∫G_σ̄·f′(y)
// at one y ~ G_σ̄ (the collision's y when there is one; otherwise the middle
// of f′'s range on the ball exactly and the rest by roulette,
// SourceIntegral). With σ̄ = 0 a step is
// a harmonic ball. At the ε-shell the walk takes U = √α g at the closest
// point, and the estimate is u(x0) = Û(x0)/√α(x0).
//
// Gradients: the first ball B0 = B(x0, R0), R0 = dist(x0, ∂Ω), is taken by
// hand with the identity's gradient
//
//   ∇U(x0) = κ mean_∂B0[U ν] − ∫ ∇G_σ̄ f′ + ∫ ∇G_σ̄ (σ̄ − σ′) U,
//
// each term in an antithetic pair (x0 ± R0ν on the sphere, x0 ± d inside,
// the second walk of a pair replaying the first one's random numbers), so
// the constant part of U cancels exactly in the odd kernels and the
// variance stays finite. The interior radius comes from FirstBallRadius.h
// (it cancels the pole of ∇G). The interior integrals take one pair per unit
// of ∫G_σ̄·(spread of σ′ on B0) (at most 16), and a pair's two walks run with
// a probability that follows its weights |σ̄ − σ′(x0 ± d)| and count 1/p:
// none where σ′ = σ̄. Then ∇u = (∇U − U ∇α/(2α))/√α, per sample, so the
// variance of the reported gradient carries the covariance of U and ∇U.
//
// Dirichlet conditions only; interior problems (a walk that leaves the far
// sphere counts as escaped and takes U = 0). Points within ε of the
// boundary take u = g at the closest point and no gradient (NaN).
#ifndef GRIDFREE_ESTIMATORS_VARYING_COEFFICIENT_WALK_H
#define GRIDFREE_ESTIMATORS_VARYING_COEFFICIENT_WALK_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/coefficients/ScreeningMajorant.h>
#include <gridfree/coefficients/VaryingCoefficients.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/NearBoundarySplitting.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/greens/GreensFunctions.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sampling/FirstBallRadius.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gridfree
{
struct VaryingCoefficientSettings
{
  // A walk stops once dist(x, ∂Ω) < ε.
  double Epsilon = 1e-4;
  // Steps (collisions included) after which a walk is stopped and counted.
  int MaxSteps = 100000;
  // The far sphere: this many boundary diagonals from its centre.
  double EscapeRadiusFactor = 8.0;
  // Estimate ∇u beside u.
  bool Gradient = false;
  // Splitting near the boundary (WalkSettings::NearBoundarySplitting): off
  // here; a Problem passes its own setting.
  bool NearBoundarySplitting = false;
};

template <int DIM>
class VaryingCoefficientEstimator
{
public:
  VaryingCoefficientEstimator(const Boundary<DIM>& boundary, const CoefficientField<DIM>& field,
    const ScreeningMajorant<DIM>& majorant, const VaryingCoefficientSettings& settings)
    : Geometry(boundary)
    , Field(field)
    , Majorant(majorant)
    , Settings(settings)
    , HasSource(field.HasSource())
    , Sample(OutputComponents(settings))
  {
    if (boundary.Components() != 1)
    {
      throw std::invalid_argument(
        "varying coefficients: the boundary values must have one component");
    }
    if (!(settings.Epsilon > 0.0))
    {
      throw std::invalid_argument("varying coefficients: epsilon must be positive");
    }
    const double escape = settings.EscapeRadiusFactor *
      std::max(boundary.Diagonal(), settings.Epsilon);
    this->Escape2 = escape * escape;
  }

  static int OutputComponents(const VaryingCoefficientSettings& s)
  {
    return s.Gradient ? 1 + DIM : 1;
  }
  int OutputComponents() const { return OutputComponents(this->Settings); }

  // Walks firstWalk .. firstWalk + walks − 1 at the probe point; each
  // sample is u then (with Gradient) ∇u. Unavailable: no gradient there
  // (within ε of the boundary, or a non-finite point).
  template <class Statistics>
  DerivativeStatus EstimatePoint(const double probeXYZ[3], std::uint64_t seed,
    std::uint64_t firstWalk, int walks, Statistics& stats, WalkCounters& counters)
  {
    Start start;
    DerivativeStatus status = DerivativeStatus::Unavailable;
    RunPointWalks<DIM>(probeXYZ, seed, firstWalk, walks, this->Sample, stats, counters,
      [&](const Vec<DIM>& x0, int w, RandomStream& rng, int& steps) {
        if (w == 0)
        {
          start = this->StartAt(x0);
          status = !this->Settings.Gradient || start.Distance >= this->Settings.Epsilon
            ? DerivativeStatus::Interior
            : DerivativeStatus::Unavailable;
        }
        return this->Walk(x0, start, rng, this->Sample.data(), steps);
      });
    return status;
  }

  // What every walk from one point shares, found once per point: the
  // coefficients there and, for gradients, the distance to the boundary,
  // the first ball's radius and its screening.
  struct Start
  {
    CoefficientSample<DIM> Coefficients;
    double Distance = std::numeric_limits<double>::quiet_NaN();
    double Radius = std::numeric_limits<double>::quiet_NaN();
    BallScreening Range;
  };

  Start StartAt(const Vec<DIM>& x0) const
  {
    Start start;
    this->Field.Evaluate(x0, start.Coefficients);
    if (!this->Settings.Gradient)
    {
      return start;
    }
    start.Distance = this->Geometry.Distance(x0);
    if (!(start.Distance >= this->Settings.Epsilon))
    {
      return start;
    }
    // The first ball need not touch the boundary (its sphere term is a walk
    // from wherever it lands). Where σ′ varies a lot on the largest ball,
    // its interior pairs, which cost two walks each, were more than half of
    // a sample's walks on the CT head; a ball a few times smaller sees a
    // narrower range of σ′ and a smaller ∫G, so it is halved while that
    // weight exceeds 1, at most kFirstBallHalvings times.
    start.Radius = start.Distance;
    start.Range = this->Majorant.ForBall(x0, start.Radius);
    for (int halving = 0; halving < kFirstBallHalvings &&
         InteriorWeight(start.Radius, start.Range) > 1.0 &&
         start.Radius > 2.0 * this->Settings.Epsilon;
         ++halving)
    {
      start.Radius *= 0.5;
      start.Range = this->Majorant.ForBall(x0, start.Radius);
    }
    return start;
  }

  // ∫G_σ̄ over B(x, r) times the largest |σ̄ − σ′| there: the size of an
  // interior pair's weights in the first ball.
  static double InteriorWeight(double r, const BallScreening& range)
  {
    const double spread = std::max(range.Highest - range.Bound, range.Bound - range.Lowest);
    if (!(spread > 0.0))
    {
      return 0.0;
    }
    const double integral = range.Bound > 0.0
      ? YukawaGreensFunction<DIM>(r, range.Bound).Integral()
      : HarmonicGreensFunction<DIM>(r).Integral();
    return integral * spread;
  }

  // One sample at x0 (`start` from StartAt(x0)) into `sample`.
  WalkEnd Walk(const Vec<DIM>& x0, const Start& start, RandomStream& rng, double* sample,
    int& steps)
  {
    steps = 0;
    this->End = WalkEnd::Boundary;
    const CoefficientSample<DIM>& atStart = start.Coefficients;
    const double sqrtAlpha = std::sqrt(atStart.Alpha);
    if (!this->Settings.Gradient)
    {
      sample[0] = this->Continue(x0, rng, steps) / sqrtAlpha;
      return this->End;
    }
    if (!(start.Distance >= this->Settings.Epsilon))
    {
      // In the ε-shell: u = g, no ball for a gradient.
      sample[0] = this->Continue(x0, rng, steps) / sqrtAlpha;
      std::fill(sample + 1, sample + 1 + DIM, std::numeric_limits<double>::quiet_NaN());
      return this->End;
    }
    double value = 0.0;
    Vec<DIM> gradient = Vec<DIM>::Zero();
    this->FirstBall(x0, start, rng, steps, value, gradient);
    sample[0] = value / sqrtAlpha;
    const Vec<DIM> g = (gradient - value * atStart.AlphaGradient / (2.0 * atStart.Alpha)) / sqrtAlpha;
    for (int i = 0; i < DIM; ++i)
    {
      sample[1 + i] = g[i];
    }
    return this->End;
  }

private:
  // The first ball's identity and its gradient, each term antithetic.
  void FirstBall(const Vec<DIM>& x0, const Start& start, RandomStream& rng, int& steps,
    double& value, Vec<DIM>& gradient)
  {
    const double r0 = start.Radius;
    const BallScreening& range = start.Range;
    const double sbar = range.Bound;
    double weightC = 1.0, kappa = DIM / r0;
    const bool screened = sbar > 0.0;
    YukawaGreensFunction<DIM> yukawa(r0, screened ? sbar : 1.0);
    HarmonicGreensFunction<DIM> harmonic(r0);
    if (screened)
    {
      weightC = yukawa.BoundaryWeight();
      kappa = yukawa.GradientWeight();
    }

    const Vec<DIM> nu = SampleUnitSphere<DIM>(rng);
    RandomStream replay = rng;
    // (The walks from the first ball split only beyond twice the point's
    // distance to the boundary: the way deep is rare on the point's own
    // scale, and the ball may be smaller than that distance.)
    const double scale = start.Distance;
    const double plus = this->Continue(x0 + r0 * nu, rng, steps, scale);
    const double minus = this->Continue(x0 - r0 * nu, replay, steps, scale);
    value = weightC * 0.5 * (plus + minus);
    gradient = kappa * 0.5 * (plus - minus) * nu;

    const double spread = std::max(range.Highest - sbar, sbar - range.Lowest);
    if (!screened && !this->HasSource && !(spread > 0.0))
    {
      return; // σ′ ≡ 0 on the ball, no source: the interior integrals vanish.
    }
    // The interior integrals from `pairs` samples: a pair's weights grow as
    // ∫G·|σ̄ − σ′|, and one sample of a large weight gave heavy tails; the
    // pairs cost walks only where σ′ differs from σ̄.
    const double integral = screened ? yukawa.Integral() : harmonic.Integral();
    const int pairs = static_cast<int>(
      std::min<double>(kMostInteriorPairs, std::max(1.0, std::ceil(integral * spread))));
    const double share = 1.0 / pairs;
    const double z = screened ? std::sqrt(sbar) * r0 : 0.0;
    for (int pair = 0; pair < pairs; ++pair)
    {
      const double r = FirstBallRadius<DIM>::Sample(r0, z, rng);
      const Vec<DIM> omega = SampleUnitSphere<DIM>(rng);
      const double q = share * FirstBallRadius<DIM>::Weight(r, r0, z);
      const double g = screened ? yukawa.Value(r) : harmonic.Value(r);
      const double dg = screened ? yukawa.GradientMagnitude(r) : harmonic.GradientMagnitude(r);
      const Vec<DIM> yPlus = x0 + r * omega, yMinus = x0 - r * omega;
      CoefficientSample<DIM> cPlus, cMinus;
      this->Field.Evaluate(yPlus, cPlus);
      this->Field.Evaluate(yMinus, cMinus);
      const TransformedCoefficients tPlus = Transform(cPlus), tMinus = Transform(cMinus);
      if (this->HasSource)
      {
        value -= q * g * 0.5 * (tPlus.Source + tMinus.Source);
        gradient -= q * dg * 0.5 * (tPlus.Source - tMinus.Source) * omega;
      }
      // Russian roulette on the pair by the size of its weights (q·g and
      // q·dg·r0 are dimensionless beside σ̄ − σ′): unbiased, as the
      // probability is fixed before the walks that it multiplies.
      const double largest =
        std::max(std::abs(sbar - tPlus.Screening), std::abs(sbar - tMinus.Screening));
      const double p =
        std::min(1.0, kInteriorRoulette * pairs * q * std::max(g, dg * r0) * largest);
      if (!(p > 0.0) || rng.NextDouble() >= p)
      {
        continue;
      }
      RandomStream replayInside = rng;
      const double aPlus = (sbar - tPlus.Screening) * this->Continue(yPlus, rng, steps, scale);
      const double aMinus =
        (sbar - tMinus.Screening) * this->Continue(yMinus, replayInside, steps, scale);
      value += q * g * 0.5 * (aPlus + aMinus) / p;
      gradient += q * dg * 0.5 * (aPlus - aMinus) / p * omega;
    }
  }

  // Û(x): a walk with delta tracking from x, adding its steps to `steps`.
  // With NearBoundarySplitting, a walk whose ball grows to twice the
  // largest it had (from twice its first, or twice `splitScale` if larger)
  // goes on as two branches of half its weight (NearBoundarySplitting.h),
  // walked in turn on the same stream; Û is the sum of what the branches
  // bring back.
  double Continue(const Vec<DIM>& x0, RandomStream& rng, int& steps, double splitScale = 0.0)
  {
    const double ceiling = NearBoundarySplit::Ceiling(
      this->Settings.NearBoundarySplitting, this->Geometry.Diagonal(), 0.0);
    this->Pending.clear();
    this->Pending.push_back(Branch{ x0, 1.0, 1.0, 0.0, 0.0, NearBoundarySplit::kMaxSplits, 0, {} });
    int branches = 1;
    bool first = true;
    double total = 0.0;
    while (!this->Pending.empty())
    {
      Branch branch = this->Pending.back();
      this->Pending.pop_back();
      total += this->WalkBranch(branch, rng, steps, first, splitScale, ceiling, branches);
      first = false;
    }
    return total;
  }

  // A branch of a walk (Continue): where it is, its weight and its share of
  // the walk (1/2 per split: roulette plays on weight/share), a ball about
  // it known to be clear (0: none), the reach at which it splits next, how
  // many splits it has left, its own steps and closest-point hint.
  struct Branch
  {
    Vec<DIM> X;
    double Weight;
    double Share;
    double KnownClear;
    double NextSplit;
    int SplitsLeft;
    int Steps;
    typename Boundary<DIM>::StepHint Hint;
  };

  // What one branch brings back: its source terms and, if it reaches the
  // ε-shell, its weight times √α g there. `first`: the walk's first branch
  // (its first ball sets where it first splits).
  double WalkBranch(Branch& branch, RandomStream& rng, int& steps, bool first, double splitScale,
    double ceiling, int& branches)
  {
    const VaryingCoefficientSettings& s = this->Settings;
    const Vec<DIM> center = this->Geometry.Center();
    double accumulated = 0.0;
    Vec<DIM> x = branch.X;
    double weight = branch.Weight;
    auto& hint = branch.Hint;
    CoefficientSample<DIM> c;
    // After a collision at y in B(x, R), B(y, R − |y − x|) lies inside the
    // domain too: the next step may use it without a closest-point query
    // when it is not much smaller (queries were most of a walk's time on
    // the CT head, and collisions most of its steps).
    double knownClear = branch.KnownClear;
    for (;; ++branch.Steps, ++steps)
    {
      const double fromCenter2 = (x - center).squaredNorm();
      if (fromCenter2 > this->Escape2 || !std::isfinite(fromCenter2))
      {
        this->Note(WalkEnd::Escaped);
        return accumulated;
      }
      const double radius =
        knownClear > 0.0 ? knownClear : this->Geometry.StepRadius(x, s.Epsilon, &hint);
      knownClear = 0.0;
      if (!(radius >= s.Epsilon))
      {
        break;
      }
      if (branch.Steps >= s.MaxSteps)
      {
        this->Note(WalkEnd::MaxSteps);
        break;
      }
      // A branch whose ball grows to twice the largest it had goes on as
      // two of half its weight (judged by the ball it steps on: any rule
      // that depends on the walk so far is unbiased).
      NearBoundarySplit::AtStep(radius, first && branch.Steps == 0, splitScale, ceiling,
        branch.NextSplit, branch.SplitsLeft, branches, [&] {
          weight *= 0.5;
          branch.Share *= 0.5;
          this->Pending.push_back(Branch{ x, weight, branch.Share, radius, branch.NextSplit,
            branch.SplitsLeft, branch.Steps, hint });
        });
      const BallScreening screening = this->Majorant.ForBall(x, radius);
      const double sbar = screening.Bound;
      if (sbar > 0.0)
      {
        const YukawaGreensFunction<DIM> green(radius, sbar);
        // The floor's share of the screening is a weight every step carries
        // (decomposition tracking): the sphere is taken with probability
        // C/keep, a collision with the rest, and both branches carry keep.
        const double floor = screening.Floor;
        const double keep = 1.0 - floor * green.Integral();
        const bool collide = floor < sbar &&
          rng.NextDouble() * keep >= green.BoundaryWeight();
        if (collide)
        {
          const Vec<DIM> offset = green.SampleOffset(rng);
          const Vec<DIM> y = x + offset;
          this->Field.Evaluate(y, c);
          const TransformedCoefficients t = Transform(c);
          accumulated -= weight * green.Integral() * t.Source;
          weight *= keep * (sbar - t.Screening) / (sbar - floor);
          if (!Roulette(weight, branch.Share, rng))
          {
            return accumulated;
          }
          const double clear = radius - offset.norm();
          if (clear >= kReuseFraction * radius && clear >= s.Epsilon)
          {
            knownClear = clear;
          }
          x = y;
          continue;
        }
        if (this->HasSource)
        {
          accumulated -= weight * this->SourceIntegral(x, green, screening, rng, c);
        }
        weight *= keep;
        if (!Roulette(weight, branch.Share, rng))
        {
          return accumulated;
        }
      }
      else if (this->HasSource)
      {
        const HarmonicGreensFunction<DIM> green(radius);
        accumulated -= weight * this->SourceIntegral(x, green, screening, rng, c);
      }
      x += radius * SampleUnitSphere<DIM>(rng);
    }
    const ClosestPointResult<DIM> hit = this->Geometry.ClosestPoint(x, hint);
    double g = 0.0;
    this->Geometry.Evaluate(x, hit, &g);
    this->Field.Evaluate(hit.point, c);
    return accumulated + weight * std::sqrt(c.Alpha) * g;
  }

  // An unbiased estimate of ∫_B G f′ on the ball B(x, R) of `green`. Where
  // the bound grid gives f′'s range [lo, hi] on the ball, the middle m of
  // it is integrated exactly and the rest, ∫G (f′ − m), sampled at one
  // y ~ G only with the probability p = (hi − lo)/2 / (kSourceRoulette ·
  // max|f′|), at least kLeastSourceProbability (counted 1/p): a ball where
  // f′ hardly varies, as most of the brain, seldom costs an evaluation of
  // the coefficients, which were a fifth of a walk's time on the CT head.
  // The added variance is at most (∫G)²·(hi − lo)/2·kSourceRoulette·max|f′|
  // per step where the range holds; as p is never 0, a range that misses
  // f′'s true extremes (sampled between lattice points) costs variance,
  // never bias.
  template <class Green>
  double SourceIntegral(const Vec<DIM>& x, const Green& green, const BallScreening& screening,
    RandomStream& rng, CoefficientSample<DIM>& c) const
  {
    const double lo = screening.SourceLowest, hi = screening.SourceHighest;
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo <= hi))
    {
      this->Field.Evaluate(x + green.SampleOffset(rng), c);
      return green.Integral() * Transform(c).Source;
    }
    const double middle = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    const double byRange = half / (kSourceRoulette * screening.SourceScale);
    const double p = std::min(1.0, std::max(kLeastSourceProbability, byRange));
    if (rng.NextDouble() >= p)
    {
      return green.Integral() * middle;
    }
    this->Field.Evaluate(x + green.SampleOffset(rng), c);
    return green.Integral() * (middle + (Transform(c).Source - middle) / p);
  }

  // Russian roulette on small weights, against the branch's share of the
  // walk (1 unless it split: halving a weight must not end it). Unbiased:
  // survivors are raised back to the threshold. False when the branch ends.
  static bool Roulette(double& weight, double share, RandomStream& rng)
  {
    const double least = kRouletteWeight * share;
    if (std::abs(weight) >= least)
    {
      return true;
    }
    if (rng.NextDouble() * least >= std::abs(weight))
    {
      return false;
    }
    weight = weight < 0.0 ? -least : least;
    return true;
  }

  // Keeps the most telling way a sample's walks ended.
  void Note(WalkEnd end)
  {
    if (this->End == WalkEnd::Boundary || end == WalkEnd::MaxSteps)
    {
      this->End = end;
    }
  }

  // The first ball's interior pair runs with probability this times its
  // weight (capped at 1): roulette only below a weight of 1/kInteriorRoulette.
  static constexpr double kInteriorRoulette = 4.0;
  // The most interior pairs of the first ball.
  static constexpr int kMostInteriorPairs = 16;
  // The first ball is at least 1/2^this of the distance to the boundary.
  static constexpr int kFirstBallHalvings = 3;
  // Walks whose weight falls below this play Russian roulette.
  static constexpr double kRouletteWeight = 0.1;
  // A collision's ball B(y, R − |y − x|) is used without a query when it is
  // at least this fraction of R.
  static constexpr double kReuseFraction = 0.5;
  // A ball's source evaluation is always made where f′'s half-range on it is
  // at least this fraction of the largest |f′|, and proportionally less
  // often below (SourceIntegral).
  static constexpr double kSourceRoulette = 0.25;
  // ... and never less often than this.
  static constexpr double kLeastSourceProbability = 1.0 / 32.0;

  const Boundary<DIM>& Geometry;
  const CoefficientField<DIM>& Field;
  const ScreeningMajorant<DIM>& Majorant;
  VaryingCoefficientSettings Settings;
  bool HasSource;
  double Escape2 = 0.0;
  WalkEnd End = WalkEnd::Boundary;
  std::vector<double> Sample;
  std::vector<Branch> Pending; // Continue's branches still to walk
};
} // namespace gridfree

#endif
