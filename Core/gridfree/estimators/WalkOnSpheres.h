// Walk on spheres for the Dirichlet problems of the paper (Sec. 2.2–2.6):
//
//   Laplace          Δu = 0                 u = g on ∂Ω          Eqn. 5
//   Poisson          Δu = f                 u = g                Eqn. 7–8
//   ScreenedPoisson  Δu − c·u = f  (c > 0)  u = g                Eqn. 9, App. B.2
//   Biharmonic       Δ²u = 0                u = g, Δu = h        Sec. 2.5, 4.3
//
// From x_k, with R_k = dist(x_k, ∂Ω) (or, far from a mesh, a cheaper radius
// of at least R_k / 1.2: Boundary::StepRadius; any ball inside the domain
// keeps the identity), one step uses the mean-value identity on the ball
// B(x_k, R_k) (FORMULAS.md §2, §3; note the sign):
//
//   u(x_k) = C_k · E[u(x_{k+1})] − ∫_B f(y) G(x_k, y) dy,   x_{k+1} ~ U(∂B),
//
// with C_k = 1 and G harmonic except for the screened equation, where G is
// the Yukawa Green's function and C_k < 1 its boundary weight. A walk carries
// the product of the C_k (its weight) and the sum of the source terms, and
// stops within ε of the boundary, taking g at the closest point (O(ε) bias,
// paper Sec. 6.1).
//
// Biharmonic: v = Δu is harmonic with v = h, and u solves Δu = v. The nested
// estimator samples y_k in each ball and runs NestedWalks inner Laplace walks
// for v(y_k) (paper Sec. 2.5). Tree walking (Sec. 4.3) reuses the outer walk:
// because v is harmonic and G radial, ∫_B G(x_k, y) v(y) dy = v(x_k) ∫_B G,
// and h at the outer walk's end is an unbiased estimate of v(x_k), so
// û(x_0) = g(x̄) − h(x̄) Σ_k R_k²/(2n) — no inner walks at all.
//
// Exterior problems (Sec. 2.6, u → 0 at infinity in 3D, u bounded in 2D): a
// walk farther than FarRadiusFactor × ρ from the centre c of the sphere
// ∂B(c, ρ) that encloses the boundary and every source is ended or returned
// to that sphere by Russian roulette (ExteriorReturn.h). ExactReturn uses the
// true return probability ρ/r as survival probability (survivors keep weight
// 1, and re-enter at the exact hitting point); RussianRoulette survives with
// probability ρ_far/r at every step beyond ρ_far and reweights survivors by
// the inverse, the textbook scheme the paper cites (Pharr et al. 13.7).
// The screened equation needs neither: far from the boundary a walk survives
// each step with probability C_k instead of carrying the weight C_k, and C_k
// falls exponentially with the ball's radius.
//
// A walk that takes MaxSteps steps is stopped and takes g at its current
// closest point (biased, counted). A walk of an equation without an exterior
// strategy (biharmonic) that leaves a far sphere is ended with boundary value
// 0 and counted as escaped.
#ifndef GRIDFREE_ESTIMATORS_WALK_ON_SPHERES_H
#define GRIDFREE_ESTIMATORS_WALK_ON_SPHERES_H

#include <gridfree/estimators/Equation.h>
#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/EquationPolicies.h>
#include <gridfree/estimators/NearBoundarySplitting.h>
#include <gridfree/estimators/PeakGuide.h>
#include <gridfree/estimators/ExteriorReturn.h>
#include <gridfree/estimators/ScreenedGuide.h>
#include <gridfree/greens/GreensFunctions.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gridfree
{
struct WalkSettings
{
  // Absolute stopping tolerance ε: a walk stops once dist(x, ∂Ω) < ε.
  double Epsilon = 1e-4;
  // Steps after which a walk is stopped and counted as truncated.
  int MaxSteps = 10000;

  Equation Problem = Equation::Laplace;
  // c of the screened Poisson equation Δu − c·u = f.
  double ScreeningCoefficient = 0.0;
  SourceSampling Sampling = SourceSampling::GreensFunction;
  BiharmonicStrategy Biharmonic = BiharmonicStrategy::TreeWalking;
  // Inner Laplace walks per step of the nested biharmonic estimator.
  int NestedWalks = 1;
  ExteriorStrategy Exterior = ExteriorStrategy::ExactReturn;
  // Walks farther than FarRadiusFactor × ρ from c take the exterior strategy.
  double FarRadiusFactor = 2.0;
  // Far sphere for equations without an exterior strategy: radius
  // EscapeRadiusFactor × boundary diagonal (at least twice the start distance).
  double EscapeRadiusFactor = 8.0;
  // Screened equation on a mesh: whether steps land by the guided mixture
  // of ScreenedGuide.h instead of uniformly (Problem builds the guide;
  // estimators made without one step uniformly).
  ScreenedSteps Screening = ScreenedSteps::Automatic;
  // Walk on spheres on a 3D mesh: whether steps lean toward the data's
  // narrow peak (PeakGuide.h; Problem builds the guide, estimators made
  // without one step uniformly).
  PeakSteps PeakGuiding = PeakSteps::Automatic;
  // Walk on stars: a start point outside the closed mixed boundary walks in
  // the domain on its other side (the exterior problem: the Laplace
  // equation, or the screened one without sources; WalkOnStars.h), as walk on spheres answers points on
  // either side of a Dirichlet boundary. Off: every start point is taken to
  // lie in the given domain.
  bool MixedBothSides = false;
  // Walk on spheres from near the boundary: most walks end close by, and
  // the few that wander deep bring back what the rest never see (sources,
  // data far away), a heavy tail that a few hundred walks misjudge. With
  // splitting, a walk whose ball grows to twice the largest it had (from
  // twice its first ball, up to a quarter of the boundary's diagonal, at most
  // 16 times and to 32 branches; for the screened equation no deeper than
  // 1/√c) goes on as two branches of half its weight, so that nearly
  // every walk carries a share of the deep ones (unbiased: any rule that
  // depends on the walk so far is). Walks from start points farther than
  // half that depth from the boundary never split (derivative walks start
  // anew on their first ball's sphere, which touches the boundary, and
  // split only beyond twice its radius: Walk's splitScale). Walk on stars
  // splits the same way by its distance to the Dirichlet part, and the
  // varying-coefficient walk by its balls. Not for the
  // biharmonic equation (NearBoundarySplitting.h). Off here (the plain
  // walks); the VTK solver, stream tracer and adaptive sampler turn it on
  // by default.
  bool NearBoundarySplitting = false;
};

enum class WalkEnd
{
  Boundary,   // reached the ε-shell: the normal case
  MaxSteps,   // truncated
  Escaped,    // left for infinity (exterior roulette or far sphere)
  Terminated  // ended by roulette on the screening weight (unbiased)
};

// The end of a walk that ran as branches (NearBoundarySplitting), for the
// counters: truncated if a branch was, else escaped if one escaped, else
// ended by roulette if one was.
inline WalkEnd MoreSevereEnd(WalkEnd a, WalkEnd b)
{
  const auto rank = [](WalkEnd e) {
    return e == WalkEnd::MaxSteps ? 3 : (e == WalkEnd::Escaped ? 2 : (e == WalkEnd::Terminated ? 1 : 0));
  };
  return rank(b) > rank(a) ? b : a;
}

// Per-point bookkeeping beside the running statistics of the value.
struct WalkCounters
{
  std::uint64_t Walks = 0;
  std::uint64_t Steps = 0;
  std::uint64_t Escaped = 0;
  std::uint64_t Truncated = 0;
  // Times a walk far outside was returned to the enclosing sphere, or (the
  // screened walk with sources) went on through a roulette step there.
  std::uint64_t Returns = 0;
  // The largest amount the value's control variate (DerivativeWalkOnSpheres:
  // C·b̄·ν, over every direction ν) could move one walk's value sample, seen
  // over the walks: with the data's bounds, how far an unseen walk's value
  // can lie (ErrorBarReliability.h).
  double ValueControlReach = 0.0;
  // The largest weight a screened walk of the point can keep: its first
  // ball's C, which every walk from the point shares (weights only shrink
  // after it); 0 when not recorded. Bounds what an unseen walk can bring
  // (ErrorBarReliability.h).
  double WeightReach = 0.0;

  double MeanSteps() const { return Walks ? double(Steps) / double(Walks) : 0.0; }
  double WeightReachOrOne() const { return this->WeightReach > 0.0 ? this->WeightReach : 1.0; }
  double EscapedFraction() const { return Walks ? double(Escaped) / double(Walks) : 0.0; }
  double TruncatedFraction() const { return Walks ? double(Truncated) / double(Walks) : 0.0; }

  void Add(const WalkCounters& other)
  {
    this->Walks += other.Walks;
    this->Steps += other.Steps;
    this->Escaped += other.Escaped;
    this->Truncated += other.Truncated;
    this->Returns += other.Returns;
    this->ValueControlReach = std::max(this->ValueControlReach, other.ValueControlReach);
    this->WeightReach = std::max(this->WeightReach, other.WeightReach);
  }
};

// The start point of a probe point (its first DIM coordinates); false when
// one of them is not finite.
template <int DIM>
bool ProbeStartPoint(const double probeXYZ[3], Vec<DIM>& x0)
{
  bool finite = true;
  for (int i = 0; i < DIM; ++i)
  {
    x0[i] = probeXYZ[i];
    finite = finite && std::isfinite(probeXYZ[i]);
  }
  return finite;
}

// A non-finite probe point: `walks` NaN samples, so every output is NaN.
template <class Statistics>
void AddNaNSamples(
  std::vector<double>& sample, int walks, Statistics& stats, WalkCounters& counters)
{
  std::fill(sample.begin(), sample.end(), std::numeric_limits<double>::quiet_NaN());
  for (int w = 0; w < walks; ++w)
  {
    stats.Add(sample.data());
  }
  counters.Walks += static_cast<std::uint64_t>(walks);
}

// The loop every estimator runs at a probe point: walks firstWalk ..
// firstWalk + walks − 1, each on its own random stream keyed by the seed,
// the point and the walk's number, so results never depend on how points
// or walks are spread over threads. walk(x0, w, rng, steps) fills `sample`
// and returns how the walk ended; non-finite start points give NaN samples.
template <int DIM, class Statistics, class WalkFunction>
void RunPointWalks(const double probeXYZ[3], std::uint64_t seed, std::uint64_t firstWalk,
  int walks, std::vector<double>& sample, Statistics& stats, WalkCounters& counters,
  WalkFunction&& walk)
{
  Vec<DIM> x0;
  if (!ProbeStartPoint<DIM>(probeXYZ, x0))
  {
    AddNaNSamples(sample, walks, stats, counters);
    return;
  }
  const std::uint64_t key = PointKey(seed, probeXYZ);
  for (int w = 0; w < walks; ++w)
  {
    RandomStream rng(key, firstWalk + static_cast<std::uint64_t>(w));
    int steps = 0;
    const WalkEnd end = walk(x0, w, rng, steps);
    stats.Add(sample.data());
    counters.Walks += 1;
    counters.Steps += static_cast<std::uint64_t>(steps);
    counters.Escaped += end == WalkEnd::Escaped ? 1 : 0;
    counters.Truncated += end == WalkEnd::MaxSteps ? 1 : 0;
  }
}

// One thread's estimator. The boundary's values hold Components() numbers
// per tuple; for the biharmonic equation they are g followed by h (so one
// closest-point query gives both), and the estimate is u followed by Δu.
template <int DIM>
class WalkOnSpheresEstimator
{
public:
  WalkOnSpheresEstimator(const Boundary<DIM>& boundary, const WalkSettings& settings,
    VolumeSource<DIM>* volume = nullptr,
    const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>())
    : Geometry(boundary)
    , Settings(settings)
    , SolutionComponents(settings.Problem == Equation::Biharmonic
          ? boundary.Components() / 2
          : boundary.Components())
    , Sources(boundary.Components(), settings.Sampling,
        UsesSources(settings.Problem) ? volume : nullptr,
        UsesSources(settings.Problem) ? concentrated : ConcentratedSourceSet<DIM>())
    , BoundaryValue(boundary.Components())
    , InnerValue(boundary.Components())
    , Accumulated(boundary.Components())
    , Sample(2 * boundary.Components())
  {
    if (settings.Problem == Equation::Biharmonic && boundary.Components() % 2 != 0)
    {
      throw std::invalid_argument("biharmonic boundary values must hold g and h");
    }
    if (settings.Problem == Equation::ScreenedPoisson && !(settings.ScreeningCoefficient > 0.0))
    {
      throw std::invalid_argument("the screening coefficient must be positive");
    }
    this->ComputeEnclosingSphere(volume, concentrated);
  }

  static bool UsesSources(Equation e)
  {
    return e == Equation::Poisson || e == Equation::ScreenedPoisson;
  }

  // Numbers per sample: the solution's components, and for the biharmonic
  // equation as many again for Δu; for the screened equation one more, the
  // walk's weight (WeightSlot()).
  int OutputComponents() const
  {
    switch (this->Settings.Problem)
    {
      case Equation::Biharmonic:
        return 2 * this->SolutionComponents;
      case Equation::ScreenedPoisson:
        return this->SolutionComponents + 1;
      default:
        return this->SolutionComponents;
    }
  }

  // Where a screened walk's sample holds its weight W = Π C_k (0 for a walk
  // ended by roulette), or −1. E[W] is the solution for g = 1: when the
  // weights of a point's walks are very uneven, its value rests on the few
  // walks that kept their weight, and walks not yet seen can dominate it
  // (ErrorBarReliability.h).
  int WeightSlot() const
  {
    return this->Settings.Problem == Equation::ScreenedPoisson ? this->SolutionComponents : -1;
  }

  // Guided steps for the screened equation (ScreenedGuide.h); null: every
  // step lands uniformly. The guide must outlive the estimator.
  void SetGuide(const ScreenedGuide<DIM>* guide) { this->Guide = guide; }
  // Steps toward the data's peak (PeakGuide.h, 3D), where no screened
  // guide leads the step.
  void SetPeakGuide(const PeakGuide<DIM>* guide) { this->Peak = guide; }

  // The weight the last walk ended with (1 for the unscreened equations).
  double LastWeight() const { return this->EndWeight; }
  // The weight after the last walk's first step (1 for the unscreened
  // equations and walks that took none): every walk from the same start
  // point shares it, and keeps no more.
  double FirstStepWeight() const { return this->FirstWeight; }

  // Centre and radius of the sphere enclosing the boundary and the sources
  // with bounded support; a volume source with unbounded support (an
  // expression) is taken as zero outside it in exterior problems.
  const Vec<DIM>& EnclosingCenter() const { return this->Center; }
  double EnclosingRadius() const { return this->Radius; }
  bool SourceSupportIsBounded() const { return this->BoundedSupport; }

  // One walk from x0; writes OutputComponents() numbers into sample.
  // The walk is compiled once per equation policy (EquationPolicies.h).
  // `splitScale` (NearBoundarySplitting): splitting starts at twice the
  // larger of it and the walk's first ball. A walk that restarts on a
  // point's first sphere (derivatives, control variates) passes that
  // sphere's radius: the sphere may touch the boundary, but the rare way
  // deep is rare only on the point's own scale.
  WalkEnd Walk(const Vec<DIM>& x0, double escapeRadius, RandomStream& rng, double* sample,
    int& steps, std::uint64_t& returns, double splitScale = 0.0)
  {
    switch (this->Settings.Problem)
    {
      case Equation::ScreenedPoisson:
        return this->WalkWith(x0, escapeRadius, rng, sample, steps, returns, splitScale,
          equations::Screened<DIM>{ this->Settings.ScreeningCoefficient });
      case Equation::Biharmonic:
        return this->WalkWith(x0, escapeRadius, rng, sample, steps, returns, splitScale,
          equations::Biharmonic<DIM>{});
      default:
        return this->WalkWith(x0, escapeRadius, rng, sample, steps, returns, splitScale,
          equations::Harmonic<DIM>{});
    }
  }

  // Runs walks number firstWalk .. firstWalk + walks - 1 from the probe point
  // probeXYZ (its first DIM coordinates are the start point; all three key
  // the random streams) and accumulates them into stats (OutputComponents()
  // components) and counters. Non-finite start points yield NaN samples.
  // `stats` is a RunningStatistics, or a SampleRecorder for walks of one
  // point split over threads.
  template <class Statistics>
  void EstimatePoint(const double probeXYZ[3], std::uint64_t seed, std::uint64_t firstWalk,
    int walks, Statistics& stats, WalkCounters& counters)
  {
    double escapeRadius = 0.0;
    const int weightSlot = this->WeightSlot();
    RunPointWalks<DIM>(probeXYZ, seed, firstWalk, walks, this->Sample, stats, counters,
      [&](const Vec<DIM>& x0, int w, RandomStream& rng, int& steps) {
        if (w == 0)
        {
          escapeRadius = this->EscapeRadius(x0);
        }
        const WalkEnd end =
          this->Walk(x0, escapeRadius, rng, this->Sample.data(), steps, counters.Returns);
        if (weightSlot >= 0)
        {
          this->Sample[weightSlot] = this->EndWeight;
          counters.WeightReach = std::max(counters.WeightReach, this->FirstWeight);
        }
        return end;
      });
  }

  // Radius of the far sphere for walks from x0 (equations without an
  // exterior strategy end there).
  double EscapeRadius(const Vec<DIM>& x0) const
  {
    return std::max(this->Settings.EscapeRadiusFactor *
        std::max(this->Geometry.Diagonal(), this->Settings.Epsilon),
      2.0 * (x0 - this->Geometry.Center()).norm());
  }

private:
  // The ball's radius cap inside a narrow source (SourceIntegrator::
  // SourceStepCap), +inf without source-density sampling.
  double SourceCap(const Vec<DIM>& x) const
  {
    return this->Sources.Active() ? this->Sources.SourceStepCap(x, this->Geometry.Diagonal())
                                  : std::numeric_limits<double>::infinity();
  }

  // A walk's branch (NearBoundarySplitting): where it is, its weight, the
  // ball radius at which it splits next and how many splits it has left,
  // its own steps and closest-point hint.
  struct Branch
  {
    Vec<DIM> X;
    double Weight;
    double NextSplit;
    int SplitsLeft;
    int Steps;
    typename Boundary<DIM>::StepHint Hint;
  };

  template <class Policy>
  WalkEnd WalkWith(Vec<DIM> x0, double escapeRadius, RandomStream& rng, double* sample,
    int& steps, std::uint64_t& returns, double splitScale, const Policy& equation)
  {
    const WalkSettings& s = this->Settings;
    constexpr bool biharmonic = Policy::IsBiharmonic;
    constexpr bool exterior = Policy::HasExteriorStrategy;
    const double farRadius = s.FarRadiusFactor * this->Radius;
    const double escape2 = escapeRadius * escapeRadius;
    std::fill(this->Accumulated.begin(), this->Accumulated.end(), 0.0);
    this->FirstWeight = 1.0;
    this->EndWeight = 0.0;
    double ballIntegrals = 0.0; // tree walking: Σ_k ∫_{B_k} G = Σ_k R_k²/(2n)
    WalkEnd end = WalkEnd::Boundary;
    const double splitCeiling = NearBoundarySplit::Ceiling(
      !biharmonic && s.NearBoundarySplitting, this->Geometry.Diagonal(), equation.ScreeningCoefficient());
    steps = 0;
    // This walk's branches still to walk (the first, then those split off);
    // each walks on the same random stream in turn, so that the walk's
    // numbers do not depend on threads.
    this->Pending.clear();
    this->Pending.push_back(Branch{ x0, 1.0, 0.0, NearBoundarySplit::kMaxSplits, 0, {} });
    int branches = 1;
    while (!this->Pending.empty())
    {
      Branch branch = this->Pending.back();
      this->Pending.pop_back();
      Vec<DIM> x = branch.X;
      double weight = branch.Weight;
      bool hasBoundaryValue = true;
      WalkEnd branchEnd = WalkEnd::Boundary;
      auto& hint = branch.Hint; // the branch's own: results never depend on threads
      for (;; ++branch.Steps, ++steps)
      {
        const double fromCenter2 = (x - this->Center).squaredNorm();
        if (exterior && fromCenter2 > farRadius * farRadius)
        {
          if (branch.Steps >= s.MaxSteps)
          {
            branchEnd = WalkEnd::MaxSteps;
            break;
          }
          const double r = std::sqrt(fromCenter2);
          if (s.Exterior == ExteriorStrategy::ExactReturn)
          {
            if (rng.NextDouble() >= ReturnProbability<DIM>(r, this->Radius))
            {
              branchEnd = WalkEnd::Escaped;
              hasBoundaryValue = false;
              break;
            }
            x = SampleExteriorReturn<DIM>(x, this->Center, this->Radius, rng);
            ++returns;
            continue;
          }
          // Textbook roulette: survive with probability ρ_far/r, reweight.
          const double survive = farRadius / r;
          if (rng.NextDouble() >= survive)
          {
            branchEnd = WalkEnd::Escaped;
            hasBoundaryValue = false;
            break;
          }
          weight /= survive;
        }
        else if (!exterior &&
          (fromCenter2 > escape2 || fromCenter2 == std::numeric_limits<double>::infinity()))
        {
          // (An infinite squared distance, beyond ~1e154, is past any far
          // sphere even when the squared escape radius overflowed as well.)
          branchEnd = WalkEnd::Escaped;
          hasBoundaryValue = false;
          break;
        }

        Vec<DIM> direction;
        bool guided = false;
        // Biharmonic walks keep the largest balls: tree walking's Σ R_k² is an
        // exit time with a long tail, and smaller balls (more, smaller terms)
        // made it heavier than a 512-walk sample variance can judge at 5σ.
        const double reach =
          biharmonic ? this->Geometry.Distance(x) : this->Geometry.StepRadius(x, s.Epsilon, &hint);
        // The ball: as far as the boundary, or smaller inside a narrow
        // source under source-density sampling (SourceStepCap); splitting
        // judges the walker by its reach.
        const double radius = !biharmonic && reach >= s.Epsilon
          ? std::max(s.Epsilon, std::min(reach, this->SourceCap(x)))
          : reach;
        // A NaN radius (a position that overflowed) ends the walk too: its
        // closest point is none, so the sample is NaN and visible.
        if (!(radius >= s.Epsilon))
        {
          break;
        }
        if (branch.Steps >= s.MaxSteps)
        {
          branchEnd = WalkEnd::MaxSteps;
          break;
        }
        // A branch that reaches a ball twice as large as it ever had (from
        // near the boundary, a rare way deep) goes on as two, each with
        // half its weight (NearBoundarySplitting).
        NearBoundarySplit::AtStep(reach, steps == 0, splitScale, splitCeiling, branch.NextSplit,
          branch.SplitsLeft, branches, [&] {
            weight *= 0.5;
            this->Pending.push_back(
              Branch{ x, weight, branch.NextSplit, branch.SplitsLeft, branch.Steps, hint });
          });

        if (this->Sources.Active() || biharmonic || Policy::WeightsSteps)
        {
          const auto green = equation.Green(radius);
          if (this->Sources.Active())
          {
            // −∫_B f G (FORMULAS.md §2: the source enters with a minus sign).
            std::fill(this->InnerValue.begin(), this->InnerValue.end(), 0.0);
            this->Sources.Accumulate(x, green, rng, this->InnerValue.data());
            for (int c = 0; c < this->SolutionComponents; ++c)
            {
              this->Accumulated[c] -= weight * this->InnerValue[c];
            }
          }
          if constexpr (biharmonic)
          {
            if (s.Biharmonic == BiharmonicStrategy::TreeWalking)
            {
              ballIntegrals += green.Integral();
            }
            else
            {
              this->AddNestedStep(x, green, rng, steps);
            }
          }
          const double boundaryWeight = green.BoundaryWeight();
          if (Policy::WeightsSteps && fromCenter2 > farRadius * farRadius)
          {
            // Far from everything: Russian roulette with survival probability
            // C instead of the weight C (unbiased, and the walk ends soon since
            // C = z/sinh z falls fast as balls grow).
            if (rng.NextDouble() >= boundaryWeight)
            {
              branchEnd = WalkEnd::Terminated;
              hasBoundaryValue = false;
              break;
            }
            if (this->Sources.Active())
            {
              // The survivor keeps its weight after gathering the source:
              // what it gathers is then no longer bounded by the weight's
              // decay, which the error-bar rule's bounds assume (Problem.h,
              // SteadyRange). Counted as a return, which turns them off.
              ++returns;
            }
          }
          else if (this->Guide && this->Guide->Guides(boundaryWeight))
          {
            // A guided step (ScreenedGuide.h): its factor varies with the
            // landing point and stays below C/(1 − α).
            double factor = boundaryWeight;
            direction = this->Guide->Step(x, radius, green, rng, factor);
            guided = true;
            weight *= factor;
            if (steps == 0)
            {
              this->FirstWeight = ScreenedGuide<DIM>::LargestFactor(boundaryWeight);
            }
          }
          else
          {
            weight *= boundaryWeight;
            if (steps == 0)
            {
              this->FirstWeight = boundaryWeight;
            }
          }
        }

        if (!guided && this->Peak)
        {
          // Toward the data's peak: the factor U/q ≤ 1/(1 − α) (PeakGuide.h).
          double factor = 1.0;
          direction = this->Peak->Step(x, radius, rng, factor);
          guided = true;
          weight *= factor;
          if (steps == 0)
          {
            this->FirstWeight *= PeakGuide<DIM>::LargestFactor();
          }
        }
        x += radius * (guided ? direction : SampleUnitSphere<DIM>(rng));
      }

      // The walk's end for the counters: truncated if a branch was, else
      // escaped if one escaped, else ended by roulette if one was.
      end = MoreSevereEnd(end, branchEnd);
      const int nc = this->SolutionComponents;
      if (hasBoundaryValue)
      {
        this->Geometry.Evaluate(
          x, this->Geometry.ClosestPoint(x, hint), this->BoundaryValue.data());
        for (int c = 0; c < nc; ++c)
        {
          this->Accumulated[c] += weight * this->BoundaryValue[c];
        }
        this->EndWeight += weight;
      }
      else
      {
        std::fill(this->BoundaryValue.begin(), this->BoundaryValue.end(), 0.0);
      }
    }

    const int nc = this->SolutionComponents;
    for (int c = 0; c < nc; ++c)
    {
      sample[c] = this->Accumulated[c];
    }
    if constexpr (biharmonic)
    {
      Policy::Finish(sample, this->BoundaryValue.data(), ballIntegrals, nc);
    }
    return end;
  }

  // Nested biharmonic step: −∫_B G v with v(y) from inner Laplace walks.
  template <class Green>
  void AddNestedStep(const Vec<DIM>& x, const Green& green, RandomStream& rng, int& steps)
  {
    const int nc = this->SolutionComponents;
    const int inner = std::max(1, this->Settings.NestedWalks);
    const Vec<DIM> d = green.SampleOffset(rng);
    const double factor = green.Integral() / static_cast<double>(inner);
    for (int w = 0; w < inner; ++w)
    {
      int innerSteps = 0;
      this->InnerLaplaceWalk(x + d, rng, innerSteps);
      steps += innerSteps;
      for (int c = 0; c < nc; ++c)
      {
        this->Accumulated[c] -= factor * this->InnerValue[nc + c];
      }
    }
  }

  // A plain Laplace walk (no exterior strategy needed: it starts inside a
  // ball of the outer walk); leaves the boundary values in InnerValue.
  void InnerLaplaceWalk(Vec<DIM> x, RandomStream& rng, int& steps)
  {
    typename Boundary<DIM>::StepHint hint;
    for (steps = 0;; ++steps)
    {
      const double radius = this->Geometry.StepRadius(x, this->Settings.Epsilon, &hint);
      if (!(radius >= this->Settings.Epsilon) || steps >= this->Settings.MaxSteps)
      {
        this->Geometry.Evaluate(x, this->Geometry.ClosestPoint(x, hint), this->InnerValue.data());
        return;
      }
      x += radius * SampleUnitSphere<DIM>(rng);
    }
  }

  void ComputeEnclosingSphere(
    VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
  {
    this->Center = this->Geometry.Center();
    this->Radius = std::max(0.5 * this->Geometry.Diagonal(), this->Settings.Epsilon);
    this->BoundedSupport = true;
    if (!UsesSources(this->Settings.Problem))
    {
      return;
    }
    auto include = [this](const Vec<DIM>& lo, const Vec<DIM>& hi) {
      for (int corner = 0; corner < (1 << DIM); ++corner)
      {
        Vec<DIM> p;
        for (int i = 0; i < DIM; ++i)
        {
          p[i] = (corner >> i) & 1 ? hi[i] : lo[i];
        }
        this->Radius = std::max(this->Radius, (p - this->Center).norm());
      }
    };
    if (volume)
    {
      Vec<DIM> lo, hi;
      if (volume->SupportBounds(lo, hi))
      {
        include(lo, hi);
      }
      else
      {
        this->BoundedSupport = false;
      }
    }
    if (concentrated.Points && !concentrated.Points->Empty())
    {
      include(concentrated.Points->BoundsMin(), concentrated.Points->BoundsMax());
    }
    if (concentrated.Curves && !concentrated.Curves->Empty())
    {
      include(concentrated.Curves->BoundsMin(), concentrated.Curves->BoundsMax());
    }
  }

  const Boundary<DIM>& Geometry;
  WalkSettings Settings;
  int SolutionComponents;
  SourceIntegrator<DIM> Sources;
  Vec<DIM> Center = Vec<DIM>::Zero();
  double Radius = 0.0;
  bool BoundedSupport = true;
  double EndWeight = 1.0;
  double FirstWeight = 1.0;
  const ScreenedGuide<DIM>* Guide = nullptr;
  const PeakGuide<DIM>* Peak = nullptr;
  // Scratch (one estimator per thread): boundary values at the walk's end,
  // inner-walk values and source integrals, the running source sum, a sample.
  std::vector<double> BoundaryValue;
  std::vector<double> InnerValue;
  std::vector<double> Accumulated;
  std::vector<double> Sample;
  std::vector<Branch> Pending;
};
} // namespace gridfree

#endif
