// Walk on spheres for the solution together with its gradient and Hessian,
// with control variates (paper Secs. 3, 4.1; FORMULAS.md §3–§5).
//
// Every walk takes its first step on B0 = B(x0, R0), R0 = dist(x0, ∂Ω), by
// hand and continues with the plain walk (WalkOnSpheres.h) from
// x1 = x0 + R0 ν, ν ~ U(S^{n−1}), which returns û(x1). With C, κ the ball's
// value and gradient weights and α, β its Hessian weights
// (GreensFunctions.h, GreensFunctionHessians.h):
//
//   û(x0)   = C û(x1)                           − ∫_B0 f G           (Eqn. 8)
//   ∇û(x0)  = κ û(x1) ν                         − ∫_B0 f ∇G          (Eqns. 13–14)
//   ∇²û(x0) = û(x1)(α ν νᵀ + β I)               − ∫_B0 [∇f ⊗ ∇G − f M]  (Eqn. 15, by parts)
//
// so the gradient costs one more source sample pair per walk and the value's
// walk is shared. For the biharmonic equation Δu = v with v harmonic, the
// first ball's source integrals have closed forms in v(x0), ∇v(x0), ∇²v(x0)
// (orthogonality of spherical harmonics against radial kernels):
//   ∫ G v = R²/(2n) v,   ∫ ∇G v = R²/(2(n+2)) ∇v,
//   ∫ ∇²G v = −v I/n + R²/(2(n+4)) ∇²v,
// and the walk's h(x̄) with the same ν gives unbiased estimates of all three.
//
// Control variates (Sec. 4.1), from running means over the previous walks
// at the same point only, so each walk's sample stays unbiased given the past
// and the sample variance of the walks stays an honest estimate (the samples
// are martingale differences around the true value):
// - value: subtract C b̄·ν, b̄ = (n/κ) ∇̄u the linear part of u on ∂B0
//   (Eqn. 16; b̄ = R ∇̄u when c = 0);
// - gradient: subtract κ m̄ ν, m̄ the running mean of û(x1) (the sphere mean
//   of u, which equals u(x0) for Laplace; Sec. 4.1.2);
// - Hessian: replace û(x1) by û(x1) − m̄ − b̄·ν and add back m̄ (α/n + β) I,
//   the exact mean of the constant part (zero for c = 0; Sec. 4.1.3);
// - sources: antithetic pairs in ∫ f ∇G and a running mean f̄ in the f·M term
//   (SourceDerivatives.h).
// With DerivativeRequest::AntitheticPairs a sample averages the walks from
// x0 + R0 ν and x0 − R0 ν (common random numbers after the first step): in
// the gradient the controls' constant and the even part of u on ∂B0 cancel
// exactly, in the value the linear part; the mean is unchanged.
//
// Points closer to the boundary than ε have no usable first ball: their
// value is g at the closest point (as in the plain walk) and their
// derivatives are estimated one-sidedly at the point 2ε (4ε, … if needed)
// from the closest point along the direction to x0 (a primitive's normal
// when x0 lies on the boundary), and reported as DerivativeStatus::OneSided.
//
// Nothing above needs the walk that continues from x1 to be walk on spheres:
// only that it returns an unbiased û(x1) and that B0 lies where the equation
// holds. The walks that continue are the `Continuation` (the plain walk,
// SphereWalkContinuation below, or walk on stars with R0 the distance to the
// whole boundary: StarDerivativeWalks.h).
#ifndef GRIDFREE_ESTIMATORS_DERIVATIVE_WALK_ON_SPHERES_H
#define GRIDFREE_ESTIMATORS_DERIVATIVE_WALK_ON_SPHERES_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/greens/GreensFunctionHessians.h>
#include <gridfree/math/DivergenceCurl.h>
#include <gridfree/greens/GreensFunctions.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/sources/SourceDerivatives.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
struct DerivativeRequest
{
  bool Gradient = false;
  bool Hessian = false;
  bool ControlVariates = true;
  // Each sample averages an antithetic pair of walks, the first steps to
  // x0 + R0 ν and x0 − R0 ν, the second walk replaying the first one's
  // random numbers: the gradient's sample is then κ ν (û⁺ − û⁻)/2, in which
  // the constant and every even part of u on the first sphere cancel. Each
  // sample costs two walks (its counters count one walk, both walks' steps).
  bool AntitheticPairs = false;
  // Z·∇u along Direction (its first DIM components).
  bool Directional = false;
  std::array<double, 3> Direction = { 1.0, 0.0, 0.0 };
  // ∇·u and ∇×u of a 3-component solution (∂/∂z = 0 in 2D).
  bool DivergenceCurl = false;
};

enum class DerivativeStatus : unsigned char
{
  Interior = 0,   // first ball centred at the point
  OneSided = 1,   // closer than ε: derivatives from a point moved inside
  Unavailable = 2 // no usable ball (degenerate geometry or non-finite point)
};

// Where each quantity sits in a walk's sample (and in the running
// statistics); -1 when absent. Gradient: nc × DIM, component-major.
// Hessian: nc × DIM × DIM, row-major per component. TailMean and SourceMean
// hold the running means the control variates need, so the statistics alone
// carry everything a later refinement of the same point needs.
struct SampleLayout
{
  int Value = 0;
  int Laplacian = -1;
  int Gradient = -1;
  int Hessian = -1;
  int Directional = -1;
  int Divergence = -1;
  int Curl = -1;
  int TailMean = -1;
  int SourceMean = -1;
  // The screened walk's weight (WalkOnSpheresEstimator::WeightSlot()).
  int Weight = -1;
  int Size = 0;
};

// The plain walk on spheres as what continues from the first ball: the
// boundary's distance, closest points and values, and its walks.
template <int DIM>
class SphereWalkContinuation
{
public:
  using BoundaryType = Boundary<DIM>;
  // The screened walk's weight has a slot of its own (SampleLayout::Weight).
  static constexpr bool kWeightSlot = true;

  SphereWalkContinuation(const Boundary<DIM>& boundary, const WalkSettings& settings,
    VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
    : Geometry(boundary)
    , Walker(boundary, settings, volume, concentrated)
  {
  }

  int Components() const { return this->Geometry.Components(); }
  double Diagonal() const { return this->Geometry.Diagonal(); }
  double Distance(const Vec<DIM>& x) const { return this->Geometry.Distance(x); }

  // The closest boundary point of x and, for a point on the boundary, the
  // direction to move in: the primitive's normal (either side may be the
  // domain). False when there is none.
  bool ClosestPoint(const Vec<DIM>& x, Vec<DIM>& point, Vec<DIM>& normal) const
  {
    const auto hit = this->Geometry.ClosestPoint(x);
    if (hit.primitive < 0)
    {
      return false;
    }
    point = hit.point;
    normal = this->Geometry.Normal(hit);
    return true;
  }

  // g at the closest point of x: the control variates' first constant.
  void Pilot(const Vec<DIM>& x, double* out) const
  {
    this->Geometry.Evaluate(x, this->Geometry.ClosestPoint(x), out);
  }

  double EscapeRadius(const Vec<DIM>& x0) const { return this->Walker.EscapeRadius(x0); }
  // A point's walks start about `centre` (walk on spheres answers either
  // side of the boundary alike).
  void StartFrom(const Vec<DIM>&) {}
  void SetGuide(const ScreenedGuide<DIM>* guide) { this->Walker.SetGuide(guide); }
  void SetPeakGuide(const PeakGuide<DIM>* guide) { this->Walker.SetPeakGuide(guide); }
  WalkEnd Walk(const Vec<DIM>& x, double escapeRadius, RandomStream& rng, double* sample,
    int& steps, std::uint64_t& returns, double splitScale = 0.0)
  {
    return this->Walker.Walk(x, escapeRadius, rng, sample, steps, returns, splitScale);
  }
  double LastWeight() const { return this->Walker.LastWeight(); }
  double FirstStepWeight() const { return this->Walker.FirstStepWeight(); }
  bool SourceSupportIsBounded() const { return this->Walker.SourceSupportIsBounded(); }

private:
  const Boundary<DIM>& Geometry;
  WalkOnSpheresEstimator<DIM> Walker;
};

template <int DIM, class Continuation = SphereWalkContinuation<DIM>>
class DerivativeWalkOnSpheres
{
public:
  using BoundaryType = typename Continuation::BoundaryType;

  DerivativeWalkOnSpheres(const typename Continuation::BoundaryType& boundary,
    const WalkSettings& settings, const DerivativeRequest& request,
    VolumeSource<DIM>* volume = nullptr,
    const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>())
    : Settings(settings)
    , Request(request)
    , Walker(boundary, settings, volume, concentrated)
    , Nc(settings.Problem == Equation::Biharmonic ? boundary.Components() / 2
                                                  : boundary.Components())
    , Sources(boundary.Components(), settings.Sampling,
        WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem) ? volume : nullptr,
        WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem) ? concentrated
                                                                   : ConcentratedSourceSet<DIM>())
    , DerivativeSources(boundary.Components(),
        WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem) ? volume : nullptr,
        WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem) ? concentrated
                                                                   : ConcentratedSourceSet<DIM>())
    , HasVolume(volume != nullptr && WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem))
  {
    if (this->Request.DivergenceCurl && this->Nc != 3)
    {
      this->Request.DivergenceCurl = false;
    }
    SampleLayout& l = this->Slots;
    int next = 0;
    l.Value = next;
    next += this->Nc;
    if (settings.Problem == Equation::Biharmonic)
    {
      l.Laplacian = next;
      next += this->Nc;
    }
    l.Gradient = next;
    next += this->Nc * DIM;
    if (this->Request.Hessian)
    {
      l.Hessian = next;
      next += this->Nc * DIM * DIM;
    }
    if (this->Request.Directional)
    {
      l.Directional = next;
      next += this->Nc;
    }
    if (this->Request.DivergenceCurl)
    {
      l.Divergence = next;
      next += 1;
      l.Curl = next;
      next += 3;
    }
    l.TailMean = next;
    next += this->Nc;
    if (this->Request.Hessian && this->HasVolume)
    {
      l.SourceMean = next;
      next += this->Nc;
    }
    if (settings.Problem == Equation::ScreenedPoisson && Continuation::kWeightSlot)
    {
      l.Weight = next;
      next += 1;
    }
    l.Size = next;
    const int components = boundary.Components();
    this->Sample.resize(l.Size);
    this->PairSample.resize(l.Size);
    this->Tail.resize(components);
    this->ValueSource.resize(components);
    this->GradientSource.resize(components * DIM);
    this->HessianSource.resize(components * DIM * DIM);
    this->SourceSample.resize(components);
    this->SourceControl.resize(components);
    this->ValueWalk.resize(2 * components);
    this->Pilot.resize(components);
    this->History = RunningStatistics(l.Size);
  }

  const SampleLayout& Layout() const { return this->Slots; }
  bool SourceSupportIsBounded() const { return this->Walker.SourceSupportIsBounded(); }
  int SolutionComponents() const { return this->Nc; }
  // The walks that continue from the first ball (their own counters).
  const Continuation& Continuations() const { return this->Walker; }
  // Guided screened steps for the walks after the first ball (ScreenedGuide.h).
  void SetGuide(const ScreenedGuide<DIM>* guide) { this->Walker.SetGuide(guide); }
  // Steps toward the data's peak (PeakGuide.h): the first ball's landing
  // point, with its weight U/q on every term that depends on it, and the
  // walks after it.
  void SetPeakGuide(const PeakGuide<DIM>* guide)
  {
    this->FirstBallPeak = guide;
    this->Walker.SetPeakGuide(guide);
  }

  // The control variates of a walk use the running means of the walks
  // before it in its block of kControlBlock walks (walks 0–255, 256–511, …),
  // not of all earlier walks: blocks are then independent, so the walks of
  // one point can run on several threads, block by block, and give the same
  // numbers as one thread. The first walk of each block falls back to the
  // pilot value and the others estimate the control coefficients from fewer
  // walks (at most 255), a small cost in variance for long runs only.
  static constexpr int kControlBlock = 256;

  // Whether the next EstimatePoint call continues the walks of the point the
  // previous call ran (firstWalk where that one stopped): the block's control
  // history is then kept, and the calls give the numbers of one call.
  void ContinueBlock(bool continuing) { this->Continuing = continuing; }

  // The running state of the current control block's walks: what a
  // continuing call uses. Progressive refinement saves it with a point's sums
  // and restores it before continuing that point's walks in a later solve
  // (RunningSumsCache), so a solve can continue inside a block.
  const RunningStatistics& BlockHistory() const { return this->History; }
  RunningStatistics& BlockHistory() { return this->History; }

  // Runs walks firstWalk .. firstWalk + walks − 1 from the probe point (the
  // random streams are keyed as in WalkOnSpheresEstimator::EstimatePoint) and
  // adds their samples to stats (Layout().Size components): a
  // RunningStatistics, or a SampleRecorder to replay later. A call that
  // starts inside a block (firstWalk not a multiple of kControlBlock) starts
  // that block's control history afresh.
  template <class Statistics>
  DerivativeStatus EstimatePoint(const double probeXYZ[3], std::uint64_t seed,
    std::uint64_t firstWalk, int walks, Statistics& stats, WalkCounters& counters)
  {
    Vec<DIM> x0;
    if (!ProbeStartPoint<DIM>(probeXYZ, x0))
    {
      AddNaNSamples(this->Sample, walks, stats, counters);
      return DerivativeStatus::Unavailable;
    }
    const double escapeRadius = this->Walker.EscapeRadius(x0);
    const std::uint64_t key = PointKey(seed, probeXYZ);

    Vec<DIM> centre = x0;
    double radius = this->Walker.Distance(x0);
    DerivativeStatus status = DerivativeStatus::Interior;
    if (!(radius >= this->Settings.Epsilon))
    {
      status = this->FindOneSidedCentre(x0, centre, radius);
    }
    this->Walker.StartFrom(centre);
    // The first ball's Green's function and Hessian kernels are the
    // equation's (EquationPolicies.h).
    const double r = status == DerivativeStatus::Unavailable ? 1.0 : radius;
    auto run = [&](const auto& equation) {
      this->Run(x0, centre, status, equation.Green(r),
        BallHessianKernels<DIM>(r, equation.ScreeningCoefficient()), escapeRadius, key,
        firstWalk, walks, stats, counters);
    };
    switch (this->Settings.Problem)
    {
      case Equation::ScreenedPoisson:
        run(equations::Screened<DIM>{ this->Settings.ScreeningCoefficient });
        break;
      case Equation::Biharmonic:
        run(equations::Biharmonic<DIM>{});
        break;
      default:
        run(equations::Harmonic<DIM>{});
    }
    return status;
  }

private:
  DerivativeStatus FindOneSidedCentre(const Vec<DIM>& x0, Vec<DIM>& centre, double& radius) const
  {
    Vec<DIM> closest, normal;
    if (!this->Walker.ClosestPoint(x0, closest, normal))
    {
      return DerivativeStatus::Unavailable;
    }
    Vec<DIM> direction = x0 - closest;
    const double length = direction.norm();
    if (length > 1e-12 * std::max(1.0, this->Walker.Diagonal()))
    {
      direction /= length;
    }
    else
    {
      direction = normal;
      if (direction.squaredNorm() == 0.0)
      {
        return DerivativeStatus::Unavailable;
      }
    }
    double offset = 2.0 * this->Settings.Epsilon;
    for (int attempt = 0; attempt < 8; ++attempt, offset *= 2.0)
    {
      centre = closest + offset * direction;
      radius = this->Walker.Distance(centre);
      if (radius >= this->Settings.Epsilon)
      {
        return DerivativeStatus::OneSided;
      }
    }
    return DerivativeStatus::Unavailable;
  }

  template <class Green, class Statistics>
  void Run(const Vec<DIM>& x0, const Vec<DIM>& centre, DerivativeStatus status,
    const Green& green, const BallHessianKernels<DIM>& kernels, double escapeRadius,
    std::uint64_t key, std::uint64_t firstWalk, int walks, Statistics& stats,
    WalkCounters& counters)
  {
    const SampleLayout& l = this->Slots;
    const int nc = this->Nc;
    const int n = DIM;
    const bool biharmonic = this->Settings.Problem == Equation::Biharmonic;
    const bool hessian = this->Request.Hessian;
    const bool controls = this->Request.ControlVariates;
    const bool available = status != DerivativeStatus::Unavailable;
    const double radius = green.Radius();
    const double weightC = green.BoundaryWeight();
    const double kappa = green.GradientWeight();
    // b̄ = (n/κ) ∇̄u. For a screened ball far larger than the screening
    // length, κ and C underflow to 0 together (both ∝ e^{−z}); the control
    // C b̄·ν is then 0 as well, not 0 · inf = NaN.
    const double linearScale = kappa > 0.0 ? DIM / kappa : 0.0;
    const double alpha = kernels.BoundaryNormalWeight();
    const double beta = kernels.BoundaryIdentityWeight();
    const double kernelMean = kernels.BoundaryKernelMean();
    Vec<DIM> direction = Vec<DIM>::Zero();
    for (int i = 0; i < DIM; ++i)
    {
      direction[i] = this->Request.Direction[i];
    }
    const double screening =
      this->Settings.Problem == Equation::ScreenedPoisson ? this->Settings.ScreeningCoefficient : 0.0;
    // Before the first walk, g at the point's closest boundary point stands
    // in for the running mean m̄ of û(x1): any constant independent of the
    // walks keeps the controls unbiased, and this one is usually close.
    if (available)
    {
      this->Walker.Pilot(centre, this->Pilot.data());
    }

    RunningStatistics& history = this->History;
    for (int w = 0; w < walks; ++w)
    {
      const std::uint64_t index = firstWalk + static_cast<std::uint64_t>(w);
      if ((w == 0 && !this->Continuing) || index % kControlBlock == 0)
      {
        history.Reset();
      }
      RandomStream rng(key, index);
      const bool haveHistory = history.SampleCount() > 0;
      const bool useControls = controls && haveHistory;
      std::fill(this->Sample.begin(), this->Sample.end(), 0.0);
      int totalSteps = 0;
      WalkEnd end = WalkEnd::Boundary;

      if (status != DerivativeStatus::Interior)
      {
        // The value comes from the plain walk at x0 (it ends at once with g
        // at the closest point); derivatives from the ball at `centre`.
        int steps = 0;
        end = this->Walker.Walk(x0, escapeRadius, rng, this->ValueWalk.data(), steps,
          counters.Returns);
        totalSteps += steps;
        if (l.Weight >= 0)
        {
          this->Sample[l.Weight] = this->Walker.LastWeight();
          counters.WeightReach = std::max(counters.WeightReach, this->Walker.FirstStepWeight());
        }
        for (int c = 0; c < nc; ++c)
        {
          this->Sample[l.Value + c] = this->ValueWalk[c];
          if (biharmonic)
          {
            this->Sample[l.Laplacian + c] = this->ValueWalk[nc + c];
          }
        }
      }

      if (available)
      {
        // First-ball source integrals (zero when there are no sources).
        std::fill(this->ValueSource.begin(), this->ValueSource.end(), 0.0);
        std::fill(this->GradientSource.begin(), this->GradientSource.end(), 0.0);
        std::fill(this->HessianSource.begin(), this->HessianSource.end(), 0.0);
        std::fill(this->SourceSample.begin(), this->SourceSample.end(), 0.0);
        if (this->Sources.Active())
        {
          this->Sources.Accumulate(centre, green, rng, this->ValueSource.data());
        }
        if (this->DerivativeSources.Active())
        {
          const double* fBar = nullptr;
          if (hessian && useControls && l.SourceMean >= 0)
          {
            for (int c = 0; c < nc; ++c)
            {
              this->SourceControl[c] = history.GetMean(l.SourceMean + c);
            }
            fBar = this->SourceControl.data();
          }
          this->DerivativeSources.Accumulate(centre, green, hessian ? &kernels : nullptr,
            screening, rng, fBar, this->GradientSource.data(),
            hessian ? this->HessianSource.data() : nullptr, this->SourceSample.data());
        }

        // The first landing point: uniform, or toward the data's peak with
        // the weight `lean` = U/q on every term that depends on it (each
        // stays an unbiased mean over the sphere; m̄ and b̄·ν, constants
        // or of mean 0 over it, keep their roles). A pair shares it.
        double lean = 1.0;
        const Vec<DIM> firstNu = this->FirstBallPeak
          ? this->FirstBallPeak->Step(centre, radius, rng, lean)
          : SampleUnitSphere<DIM>(rng);
        const RandomStream replay = rng; // the pair's second walk replays the first's numbers
        const int sides = this->Request.AntitheticPairs ? 2 : 1;
        for (int side = 0; side < sides; ++side)
        {
          if (side == 1)
          {
            this->PairSample = this->Sample;
            rng = replay;
          }
          const Vec<DIM> nu = side == 0 ? firstNu : Vec<DIM>(-firstNu);
          int steps = 0;
          const WalkEnd tailEnd = this->Walker.Walk(
            centre + radius * nu, escapeRadius, rng, this->Tail.data(), steps, counters.Returns,
            radius);
          totalSteps += steps + 1;
          if (status == DerivativeStatus::Interior)
          {
            // A pair reports how its second walk ended if that one escaped
            // or was cut off.
            end = side == 0 || tailEnd != WalkEnd::Boundary ? tailEnd : end;
            if (l.Weight >= 0)
            {
              // The value is C·(tail − …): the first ball's weight times the
              // tail walk's, so no walk from this point keeps more than C.
              this->Sample[l.Weight] = weightC * this->Walker.LastWeight() * lean;
              counters.WeightReach = std::max(counters.WeightReach, weightC);
            }
          }
          const Mat<DIM> nuNu = nu * nu.transpose();
          const Mat<DIM> identity = Mat<DIM>::Identity();

          for (int c = 0; c < nc; ++c)
          {
            const double tail = this->Tail[c] * lean;
            const double h = biharmonic ? this->Tail[nc + c] * lean : 0.0;
            double mBar = controls ? this->Pilot[c] : 0.0;
            Vec<DIM> bBar = Vec<DIM>::Zero();
            if (useControls)
            {
              mBar = history.GetMean(l.TailMean + c);
              for (int i = 0; i < DIM; ++i)
              {
                bBar[i] = linearScale * history.GetMean(l.Gradient + c * DIM + i);
              }
            }
            const double linear = bBar.dot(nu) * lean;

            if (status == DerivativeStatus::Interior)
            {
              counters.ValueControlReach =
                std::max(counters.ValueControlReach, weightC * bBar.norm() * lean);
              double value = weightC * (tail - linear) - this->ValueSource[c];
              if (biharmonic)
              {
                value -= radius * radius / (2.0 * n) * h;
                this->Sample[l.Laplacian + c] = h;
              }
              this->Sample[l.Value + c] = value;
            }

            Vec<DIM> gradient = kappa * (tail - mBar * lean) * nu;
            for (int i = 0; i < DIM; ++i)
            {
              gradient[i] -= this->GradientSource[c * DIM + i];
            }
            if (biharmonic)
            {
              gradient -= (n * radius / (2.0 * (n + 2.0))) * h * nu;
            }
            for (int i = 0; i < DIM; ++i)
            {
              this->Sample[l.Gradient + c * DIM + i] = gradient[i];
            }

            if (hessian)
            {
              Mat<DIM> hess = (tail - mBar * lean - linear) * (alpha * nuNu + beta * identity) +
                mBar * kernelMean * identity;
              if (biharmonic)
              {
                hess += h * identity / n - h * (n + 2.0) * (n * nuNu - identity) / (2.0 * (n + 4.0));
              }
              for (int i = 0; i < DIM; ++i)
              {
                for (int j = 0; j < DIM; ++j)
                {
                  this->Sample[l.Hessian + (c * DIM + i) * DIM + j] =
                    hess(i, j) - this->HessianSource[(c * DIM + i) * DIM + j];
                }
              }
            }
            if (l.Directional >= 0)
            {
              double dz = 0.0;
              for (int i = 0; i < DIM; ++i)
              {
                dz += direction[i] * this->Sample[l.Gradient + c * DIM + i];
              }
              this->Sample[l.Directional + c] = dz;
            }
            this->Sample[l.TailMean + c] = tail;
            if (l.SourceMean >= 0)
            {
              this->Sample[l.SourceMean + c] = this->SourceSample[c];
            }
          }
          if (l.Divergence >= 0)
          {
            this->AddDivergenceCurl();
          }
        }
        if (sides == 2)
        {
          for (int i = 0; i < l.Size; ++i)
          {
            this->Sample[i] = 0.5 * (this->PairSample[i] + this->Sample[i]);
          }
        }
      }

      history.Add(this->Sample.data());
      stats.Add(this->Sample.data());
      counters.Walks += 1;
      counters.Steps += static_cast<std::uint64_t>(totalSteps);
      counters.Escaped += end == WalkEnd::Escaped ? 1 : 0;
      counters.Truncated += end == WalkEnd::MaxSteps ? 1 : 0;
    }
  }

  // J(i, j) = ∂u_i/∂x_j of a 3-component solution, ∂/∂z = 0 in 2D.
  void AddDivergenceCurl()
  {
    const SampleLayout& l = this->Slots;
    double curl[3];
    DivergenceAndCurl<DIM>(
      [&](int i, int j) { return this->Sample[l.Gradient + i * DIM + j]; },
      this->Sample[l.Divergence], curl);
    for (int a = 0; a < 3; ++a)
    {
      this->Sample[l.Curl + a] = curl[a];
    }
  }

  WalkSettings Settings;
  DerivativeRequest Request;
  Continuation Walker;
  const PeakGuide<DIM>* FirstBallPeak = nullptr; // the first landing point's guide, or null
  int Nc;
  SourceIntegrator<DIM> Sources;
  SourceDerivativeIntegrator<DIM> DerivativeSources;
  bool HasVolume;
  SampleLayout Slots;
  // Per-thread scratch, sized once.
  std::vector<double> Sample;
  std::vector<double> PairSample; // the first walk's sample of a pair
  std::vector<double> Tail;
  std::vector<double> ValueSource;
  std::vector<double> GradientSource;
  std::vector<double> HessianSource;
  std::vector<double> SourceSample;
  std::vector<double> SourceControl;
  std::vector<double> ValueWalk;
  std::vector<double> Pilot;
  // Running means of the walks before, in the current control block.
  RunningStatistics History;
  bool Continuing = false;
};
} // namespace gridfree

#endif
