// A problem built once and answered in batches: the boundary (geometry,
// hierarchy and values), the equation and its settings, and the sources.
// This is the one door into the estimators for the VTK filters and for any
// C++ program: build a Problem when the boundary or the equation changes,
// then ask it for estimates at any list of points, as often as needed,
// without rebuilding anything.
//
// A batch (Batch.h) runs every point's walks on all threads (TBB) while the
// calling thread reports progress and polls for abort (BatchScheduler.h).
// The numbers depend only on the seed, each point's coordinates and the walk
// numbers, never on the thread count. A batch may resume from running sums
// kept by the previous one (progressive refinement, paper Sec. 5.2;
// RunningSumsCache.h), bit for bit as if all walks ran at once.
#ifndef GRIDFREE_PROBLEM_PROBLEM_H
#define GRIDFREE_PROBLEM_PROBLEM_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/coefficients/ScreeningMajorant.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/VaryingCoefficientWalk.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/geometry/RayParity.h>
#include <gridfree/problem/Batch.h>
#include <gridfree/problem/BatchScheduler.h>
#include <gridfree/sources/PolynomialShift.h>
#include <gridfree/sources/SourceSet.h>
#include <gridfree/stars/StarDerivativeWalks.h>
#include <gridfree/stars/WalkOnStars.h>
#include <gridfree/statistics/ErrorBarReliability.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/statistics/RunningSumsCache.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace gridfree
{
template <int DIM>
class Problem
{
  // Runs the batches (Estimate) with the boundary, settings and sources.
  friend class BatchScheduler<DIM>;

public:
  // Throws std::invalid_argument for a problem no walk can solve (no
  // boundary, ε not positive, a screened equation without screening, a
  // biharmonic boundary without g and h).
  Problem(std::shared_ptr<const Boundary<DIM>> boundary, const WalkSettings& settings,
    std::shared_ptr<const SourceSet<DIM>> sources = nullptr)
    : Shape(std::move(boundary))
    , Walk(settings)
    , Sources(std::move(sources))
  {
    this->Initialize();
  }

  // A problem with Neumann or Robin conditions on part of the boundary,
  // solved by walk on stars (WalkOnStars.h; derivatives: a first ball in
  // the domain, then walk on stars, StarDerivativeWalks.h). Throws for what
  // walk on stars cannot solve (the biharmonic equation; Neumann
  // conditions alone without screening).
  Problem(std::shared_ptr<const MixedBoundary<DIM>> mixed, const WalkSettings& settings,
    std::shared_ptr<const SourceSet<DIM>> sources = nullptr)
    : Shape(mixed ? (mixed->HasDirichlet() ? mixed->SharedDirichlet() : mixed->SharedReflecting())
                  : nullptr)
    , Mixed(std::move(mixed))
    , Walk(settings)
    , Sources(std::move(sources))
  {
    this->Initialize();
    // The estimator's own checks, once, here rather than on a worker thread.
    WalkOnStarsEstimator<DIM> check(*this->Mixed, this->Walk);
    (void)check;
  }

  // A problem of the equation with varying coefficients, ∇·(α∇u) − σu = f
  // with Dirichlet values (VaryingCoefficientWalk.h): settings.Problem must
  // be Equation::VaryingCoefficients; the source is the coefficients' f.
  // Answers values and gradients (no Hessian, directional derivative,
  // divergence or curl).
  Problem(std::shared_ptr<const Boundary<DIM>> boundary, const WalkSettings& settings,
    std::shared_ptr<const CoefficientModel<DIM>> coefficients)
    : Shape(std::move(boundary))
    , Walk(settings)
    , Coefficients(std::move(coefficients))
  {
    if (settings.Problem != Equation::VaryingCoefficients)
    {
      throw std::invalid_argument("coefficients are given: the equation must be the one with "
                                  "varying coefficients");
    }
    if (!this->Coefficients || !this->Coefficients->Field || !this->Coefficients->Majorant)
    {
      throw std::invalid_argument("the equation with varying coefficients needs its coefficients "
                                  "and a screening majorant");
    }
    this->Initialize();
    VaryingCoefficientEstimator<DIM> check(*this->Shape, *this->Coefficients->Field,
      *this->Coefficients->Majorant, this->VaryingSettings(false));
    (void)check;
  }

  // The coefficients of a problem of the varying equation, or null.
  const CoefficientModel<DIM>* GetCoefficients() const { return this->Coefficients.get(); }

  // The mixed boundary of a walk-on-stars problem, or null.
  const MixedBoundary<DIM>* GetMixedBoundary() const { return this->Mixed.get(); }

  // Whether a mixed problem's points outside its closed boundary get the
  // exterior problem's answers (WalkSettings::MixedBothSides, where the
  // exterior is solved: AnswersBothSides). When not, walks from such points
  // would take them for inside: callers leave them out (MixedBoundary::Inside).
  bool AnswersOutside() const
  {
    const bool sources = this->Walk.Problem != Equation::Laplace && this->Sources &&
      !this->Sources->Empty();
    return this->Mixed && AnswersBothSides(*this->Mixed, this->Walk, sources);
  }

private:
  void Initialize()
  {
    if (!this->Shape || this->Shape->Empty())
    {
      throw std::invalid_argument("the problem has no boundary");
    }
    if (!(this->Walk.Epsilon > 0.0))
    {
      throw std::invalid_argument("epsilon must be positive");
    }
    if (this->Walk.Problem == Equation::Biharmonic && this->Shape->Components() % 2 != 0)
    {
      throw std::invalid_argument("biharmonic boundary values must hold g and h");
    }
    if (this->Walk.Problem == Equation::ScreenedPoisson && !(this->Walk.ScreeningCoefficient > 0.0))
    {
      throw std::invalid_argument("the screening coefficient must be positive");
    }
    if (this->Walk.Problem == Equation::VaryingCoefficients && !this->Coefficients)
    {
      throw std::invalid_argument("the equation with varying coefficients needs its coefficients");
    }
    this->ResolveSourceSampling();
    // A mixed problem's flux makes its values vary even with constant g, and
    // so do varying coefficients.
    this->ConstantData = !this->Mixed && !this->Coefficients && this->Shape->ConstantValues() &&
      (!this->Sources || this->Sources->Empty());
    // The plain screened walk with Dirichlet data of known range (a table's,
    // or a function's sampled on the boundary) gives walk values W·g + (1 − W)·v
    // with 0 ≤ W ≤ 1 and v from a volume source of known range
    // (SteadyRange): bounded, which lets uneven weights pass where no unseen
    // walk could move the mean far (ErrorBarReliability.h).
    if (this->GuidesScreenedSteps())
    {
      auto guide =
        std::make_shared<const ScreenedGuide<DIM>>(*this->Shape, this->Walk.ScreeningCoefficient);
      if (!guide->Empty())
      {
        this->Guide = std::move(guide);
      }
    }
    if (this->MayGuideTowardPeak())
    {
      auto peak = std::make_shared<const PeakGuide<DIM>>(
        *this->Shape, this->Walk.Problem == Equation::ScreenedPoisson ? this->Walk.ScreeningCoefficient : 0.0);
      if (peak->Found() && (this->Walk.PeakGuiding == PeakSteps::Guided ||
                             peak->StandsOut() >= PeakGuide<DIM>::kStandsOut))
      {
        this->Peak = std::move(peak);
      }
    }
    if (!this->Guide && !this->Peak)
    {
      this->Guide = this->LeadingGuide();
      this->GuideLeadsMildly = this->Guide != nullptr;
    }
    // (Guided weights can exceed 1: the bounds below do not hold for them.)
    // The Laplace and Poisson walks without sources give convex
    // combinations of g (branches of near-boundary splitting share a walk's
    // weight), so their values lie within g's range too; 0 is theirs only
    // for a walk that escaped (the exterior), whose points ErrorRule leaves
    // to the plain rule. g's range is a table's, or a function's sampled on
    // the boundary (Boundary::ValueRanges).
    const bool screened = this->Walk.Problem == Equation::ScreenedPoisson;
    const bool harmonic = (this->Walk.Problem == Equation::Laplace ||
                            this->Walk.Problem == Equation::Poisson) &&
      (!this->Sources || this->Sources->Empty());
    if ((screened || harmonic) && !this->Mixed && !this->Coefficients && !this->Guide &&
      !this->Peak)
    {
      if (screened && this->SampledSourceLow.empty() && this->SourceStatesNoRange())
      {
        // Sampling chosen by hand: Automatic's map, which samples f, was
        // not built.
        this->KeepSampledSourceRange(this->MakeSourceDensityMap().get());
      }
      const std::size_t nc = static_cast<std::size_t>(this->Shape->Components());
      std::vector<double> low, high, steadyLow(nc), steadyHigh(nc);
      bool known = this->Shape->ValueRanges(low, high);
      for (std::size_t k = 0; k < nc && known; ++k)
      {
        const int c = static_cast<int>(k);
        known = this->SteadyRange(c, steadyLow[k], steadyHigh[k]);
        if (screened)
        {
          low[k] = std::min(low[k], 0.0);
          high[k] = std::max(high[k], 0.0);
        }
      }
      if (known)
      {
        this->BoundedWalks.WalkLow = std::move(low);
        this->BoundedWalks.WalkHigh = std::move(high);
        this->BoundedWalks.SteadyLow = std::move(steadyLow);
        this->BoundedWalks.SteadyHigh = std::move(steadyHigh);
      }
    }
    this->BuildSourceDensity();
  }

  // Guided steps for the screened equation (ScreenedGuide.h): they bring
  // the walks to large data, where uniform steps rarely land once the
  // screening length 1/√c is short beside the domain (Automatic: √c × the
  // diagonal ≥ 10; below it, uniform steps' tails are light, and a guide
  // pointing one way can make them heavier, as for the radial I0 data of
  // ErrorBarReliability.BoundedDataWithUnevenWeightsIsNotFlagged at c = 9).
  // Automatic leaves sources to uniform steps: their answer also comes from
  // the volume, which the guide does not see.
  bool GuidesScreenedSteps() const
  {
    if (this->Walk.Problem != Equation::ScreenedPoisson || this->Mixed || this->Coefficients ||
      this->Walk.Screening == ScreenedSteps::Uniform)
    {
      return false;
    }
    if (this->Walk.Screening == ScreenedSteps::Guided)
    {
      return true;
    }
    return std::sqrt(this->Walk.ScreeningCoefficient) * this->Shape->Diagonal() >= 10.0 &&
      (!this->Sources || this->Sources->Empty());
  }

  // Automatic's guided steps under mild screening (√c × the diagonal below
  // 10, where GuidesScreenedSteps leaves the steps uniform), where the
  // guide's directions agree across the domain (ScreenedGuide::Agreement at
  // least kLeadingAgreement over the centres of an 8-cell lattice inside the
  // boundary: InteriorLattice): the data lead one way, as a plane wave's do, and a point's value
  // comes from rare walks that reach the far side, which uniform steps find
  // too seldom (the unit disk with e^{3x} at c = 9, the unit ball with
  // e^{2x} at c = 4: Documentation/ErrorBars.md). Not where the data come
  // from all around (radial data: the directions cancel), where leaning one
  // way made the tails heavier; nor for peaks, which the peak steps take
  // first in 3D; nor where either kind of step was set by hand.
  static constexpr double kLeadingAgreement = 0.9;
  static constexpr double kLeadingLeastConcentration = 0.5; // ScreenedGuide::SetLeastConcentration
  std::shared_ptr<const ScreenedGuide<DIM>> LeadingGuide() const
  {
    if (this->Walk.Problem != Equation::ScreenedPoisson || this->Mixed || this->Coefficients ||
      this->Walk.Screening != ScreenedSteps::Automatic ||
      this->Walk.PeakGuiding != PeakSteps::Automatic || (this->Sources && !this->Sources->Empty()) ||
      !(this->Walk.ScreeningCoefficient > 0.0))
    {
      return nullptr;
    }
    auto guide =
      std::make_shared<ScreenedGuide<DIM>>(*this->Shape, this->Walk.ScreeningCoefficient);
    if (guide->Empty())
    {
      return nullptr;
    }
    guide->SetLeastConcentration(kLeadingLeastConcentration);
    return guide->Agreement(InteriorLattice<DIM>(*this->Shape, 8)) >= kLeadingAgreement
      ? guide
      : nullptr;
  }

  // Steps toward the data's peak (PeakGuide.h): walk on spheres with
  // Dirichlet data, for the Laplace, Poisson and screened
  // equations (in 2D the screened equation only), where no screened guide
  // leads the steps. Automatic also leaves alone problems with sources (their answer comes from the volume
  // too), screened problems whose steps were asked to be uniform, and
  // (SetPolynomialShift) the data of a polynomial control variate, g − P,
  // whose largest values are a fit's residuals rather than a peak.
  bool MayGuideTowardPeak() const
  {
    const Equation e = this->Walk.Problem;
    if (this->Mixed || this->Coefficients || this->Guide ||
      this->Walk.PeakGuiding == PeakSteps::Uniform ||
      !(e == Equation::Laplace || e == Equation::Poisson || e == Equation::ScreenedPoisson) ||
      (DIM == 2 && e != Equation::ScreenedPoisson))
    {
      return false;
    }
    if (this->Walk.PeakGuiding == PeakSteps::Guided)
    {
      return true;
    }
    const bool sources = e != Equation::Laplace && this->Sources && !this->Sources->Empty();
    return !sources &&
      !(e == Equation::ScreenedPoisson && this->Walk.Screening == ScreenedSteps::Uniform);
  }

  // The range [low, high] of v for component c, where one screened walk (or
  // a derivative walk's value) gives W·g − S = W·g + (1 − W)·v, S what it
  // gathers from the sources; false when S is not bounded. A step on
  // B(x, R) adds W_k·Σ w_j f(y_j), W_k the weight before the step;
  // Green's-function sampling takes one y with w = ∫G, the
  // multiple-importance and source-density estimators two with w ≤ ∫G each
  // (their balance heuristic's weights), uniform sampling w = |B|·G(y),
  // unbounded near x. And c∫G = 1 − C on every ball (the constant solution
  // of the screened equation), while the step multiplies W by C, so
  // Σ W_k·∫G_k = (1 − W)/c: with G's sampling v = −f̄/c, f̄ a weighted mean
  // of f's samples, in [−f_max/c, −f_min/c]; with two samples v lies in
  // 2·[−max(0, f_max), −min(0, f_min)]/c. Point and curve sources are
  // sampled by G itself (unbounded near them).
  bool SteadyRange(int c, double& low, double& high) const
  {
    low = high = 0.0;
    if (!this->Sources || this->Sources->Empty())
    {
      return true;
    }
    const SourceSet<DIM>& s = *this->Sources;
    if ((s.Points && !s.Points->Empty()) || (s.Curves && !s.Curves->Empty()) ||
      !s.MakeVolume || this->Walk.Sampling == SourceSampling::Uniform ||
      !(this->Walk.ScreeningCoefficient > 0.0))
    {
      return false;
    }
    double fLow = 0.0, fHigh = 0.0;
    const std::unique_ptr<VolumeSource<DIM>> volume = s.MakeVolume(this->Shape->Diagonal());
    if (!volume)
    {
      return false;
    }
    if (!volume->ValueBounds(c, fLow, fHigh))
    {
      // A source that states no range (an expression of x, y, z): its
      // samples' (SampledSourceRange), with the 0 it takes outside its
      // support.
      const std::size_t k = static_cast<std::size_t>(c);
      if (k >= this->SampledSourceLow.size())
      {
        return false;
      }
      fLow = this->SampledSourceLow[k];
      fHigh = this->SampledSourceHigh[k];
      Vec<DIM> lo, hi;
      if (volume->SupportBounds(lo, hi))
      {
        fLow = std::min(fLow, 0.0);
        fHigh = std::max(fHigh, 0.0);
      }
    }
    const double sc = this->Walk.ScreeningCoefficient;
    if (this->Walk.Sampling == SourceSampling::GreensFunction)
    {
      low = -fHigh / sc;
      high = -fLow / sc;
    }
    else
    {
      low = -2.0 * std::max(fHigh, 0.0) / sc;
      high = -2.0 * std::min(fLow, 0.0) / sc;
    }
    return std::isfinite(low) && std::isfinite(high);
  }

public:

  const Boundary<DIM>& GetBoundary() const { return *this->Shape; }

  // Whether every walk's value lies in a known range (the Dirichlet data's
  // and the source's), which lets the error bars' signs tell an unseen
  // walk's reach (ErrorBar, ErrorBarReliability.h).
  bool WalkValuesBounded() const { return !this->BoundedWalks.WalkLow.empty(); }
  // Whether screened walks take guided steps (GuidesScreenedSteps).
  bool StepsAreGuided() const { return this->Guide != nullptr; }
  // Whether steps lean toward the data's peak (MayGuideTowardPeak).
  bool StepsLeanTowardPeak() const { return this->Peak != nullptr; }
  const std::shared_ptr<const Boundary<DIM>>& SharedBoundary() const { return this->Shape; }
  const WalkSettings& Settings() const { return this->Walk; }
  const SourceSet<DIM>* GetSources() const { return this->Sources.get(); }

  // The polynomial P of a problem built for w = u − P (PolynomialShift.h:
  // its boundary reads g − P, its source is f − (ΔP − c·P)); null for a
  // plain problem. Estimate then adds P, ∇P, ∇²P and Z·∇P to what the
  // walks of w give, so every answer is u's. Set once, before the problem
  // is shared; the caller has checked that the boundary and sources are w's.
  // Points outside the closed mesh (by ray parity, RayParity.h: a contour's
  // stray flipped triangle does not move a point outside) are NaN, for
  // w = u − P grows like P at infinity, which the exterior walks do not
  // represent (BatchSummary::PointsOutsideShift counts them).
  void SetPolynomialShift(std::shared_ptr<const PolynomialShift<DIM>> shift)
  {
    if (shift && (this->Mixed || this->Coefficients ||
                   this->Walk.Problem == Equation::Biharmonic || this->SolutionComponents() != 1))
    {
      throw std::invalid_argument("the polynomial control variate takes Dirichlet problems of "
                                  "the Laplace, Poisson and screened Poisson equations with one "
                                  "component");
    }
    this->Shift = std::move(shift);
    if (this->Shift && this->Walk.PeakGuiding == PeakSteps::Automatic)
    {
      this->Peak.reset();
    }
    if (this->Shift && this->GuideLeadsMildly)
    {
      this->Guide.reset(); // g − P leads nowhere in particular
    }
  }
  const PolynomialShift<DIM>* GetPolynomialShift() const { return this->Shift.get(); }

  // Adds P's part at x to a point's statistics of w (see SetPolynomialShift).
  void AddShift(const std::array<double, 3>& xyz, const SampleLayout& layout,
    const DerivativeRequest& derivatives, RunningStatistics& stats) const
  {
    Vec<DIM> x;
    for (int i = 0; i < DIM; ++i)
    {
      x[i] = xyz[static_cast<std::size_t>(i)];
    }
    stats.ShiftMean(layout.Value, this->Shift->Value(x));
    if (layout.Gradient >= 0 || layout.Directional >= 0)
    {
      const Vec<DIM> g = this->Shift->Gradient(x);
      for (int i = 0; i < DIM && layout.Gradient >= 0; ++i)
      {
        stats.ShiftMean(layout.Gradient + i, g[i]);
      }
      if (layout.Directional >= 0)
      {
        double dz = 0.0;
        for (int i = 0; i < DIM; ++i)
        {
          dz += derivatives.Direction[static_cast<std::size_t>(i)] * g[i];
        }
        stats.ShiftMean(layout.Directional, dz);
      }
    }
    if (layout.Hessian >= 0)
    {
      const Mat<DIM> h = this->Shift->Hessian(x);
      for (int i = 0; i < DIM; ++i)
      {
        for (int j = 0; j < DIM; ++j)
        {
          stats.ShiftMean(layout.Hessian + i * DIM + j, h(i, j));
        }
      }
    }
  }

  // Components of the solution (g's, or half of g and h's for the
  // biharmonic equation).
  int SolutionComponents() const
  {
    return this->Walk.Problem == Equation::Biharmonic ? this->Shape->Components() / 2
                                                      : this->Shape->Components();
  }

  // The slots of each point's statistics for this request: the value (and
  // Δu for the biharmonic equation) first, then the derivatives asked for.
  SampleLayout Layout(const BatchRequest& request) const
  {
    if (this->Coefficients)
    {
      // u, then ∇u when asked for.
      const DerivativeRequest& d = request.Derivatives;
      if (d.Hessian || d.Directional || d.DivergenceCurl)
      {
        throw std::invalid_argument("the equation with varying coefficients gives values and "
                                    "gradients only (no Hessian, directional derivative, "
                                    "divergence or curl)");
      }
      SampleLayout layout;
      layout.Gradient = d.Gradient ? 1 : -1;
      layout.Size = d.Gradient ? 1 + DIM : 1;
      return layout;
    }
    if (request.DerivativeWalks() && this->Mixed)
    {
      auto volume = this->MakeVolume();
      return StarDerivativeWalks<DIM>(
        *this->Mixed, this->Walk, request.Derivatives, volume.get(), this->Concentrated())
        .Layout();
    }
    if (request.DerivativeWalks())
    {
      auto volume = this->MakeVolume();
      return DerivativeWalkOnSpheres<DIM>(
        *this->Shape, this->Walk, request.Derivatives, volume.get(), this->Concentrated())
        .Layout();
    }
    SampleLayout layout;
    const int nc = this->SolutionComponents();
    layout.Value = 0;
    layout.Laplacian = this->Walk.Problem == Equation::Biharmonic ? nc : -1;
    // Walk on stars' screened walks keep no weight slot (their weights
    // fall at Neumann and Robin hits as well as on spheres).
    layout.Weight = this->Walk.Problem == Equation::ScreenedPoisson && !this->Mixed ? nc : -1;
    layout.Size = this->Walk.Problem == Equation::Biharmonic ? 2 * nc
      : layout.Weight >= 0                                   ? nc + 1
                                                             : nc;
    return layout;
  }

  // Whether a finished point's error bar can be trusted, from its
  // statistics and counters (ErrorBarReliability.h): what the sink can
  // report per point.
  ErrorBarCheck ErrorBar(const RunningStatistics& stats, const WalkCounters& counters,
    const SampleLayout& layout, DerivativeStatus status = DerivativeStatus::Interior) const
  {
    // Guided steps make weights uneven on purpose (they carry e^{−√c·path}
    // for walks drawn toward large data), so their spread is no sign of an
    // unseen walk: only the values' own spread is judged.
    return CheckErrorBar(stats, layout.Value, this->SolutionComponents(),
      this->Guide || this->Peak ? -1 : layout.Weight, this->SpreadPossible(counters, status),
      this->ErrorRule(counters),
      counters.ValueControlReach, counters.WeightReachOrOne());
  }

  // The rule a point's error bar is judged by: with the bounds of its walk
  // values where they are known (a value table or a function sampled on the
  // boundary, Boundary::ValueRanges, and the Laplace or Poisson walk without sources
  // or the screened walk with no sources or a volume source of known
  // range), for walks never returned from far outside (nor escaped to it,
  // but for the screened walk, whose bounds hold 0). A value's control
  // variate may move a sample beyond them by WalkCounters::ValueControlReach,
  // the slack CheckErrorBar is given.
  const ErrorBarRule& ErrorRule(const WalkCounters& counters) const
  {
    static const ErrorBarRule plain;
    const bool bounded = !this->BoundedWalks.WalkLow.empty() && counters.Returns == 0 &&
      (this->Walk.Problem == Equation::ScreenedPoisson || counters.Escaped == 0);
    return bounded ? this->BoundedWalks : plain;
  }

  // Whether the walks of a point with these counters could have given
  // different values: they took steps, and the data are not constant. A
  // point closer than ε (DerivativeStatus::OneSided) takes g at its closest
  // point as its value, exactly, whatever steps its derivative walks took:
  // a value without spread is then no missing tail.
  bool SpreadPossible(
    const WalkCounters& counters, DerivativeStatus status = DerivativeStatus::Interior) const
  {
    return counters.Steps > 0 && !this->ConstantData && status != DerivativeStatus::OneSided;
  }

  // Runs request.WalksPerPoint walks at every point (the first DIM of its
  // three coordinates are the start point; all three key its random
  // streams) and hands each finished point to `sink`. With `kept`, the batch
  // continues from the sums it holds when they fit (same points, same
  // layout, no more walks than asked, a target that allows it:
  // RunningSumsCache::CanResume), each point from its own walk count, and
  // keeps its own; the caller clears `kept` when anything else changed.
  // Aborted with `kept`, the batch still hands every point that holds walks
  // to `sink` (those cut short with the walks they ran, those not reached
  // with the kept ones) and keeps them all, so that the next batch
  // continues where this one stopped; points without any walk never reach
  // `sink`. Exceptions of the estimators propagate.
  BatchSummary Estimate(const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request, const PointSink& sink,
    const BatchProgressCallback& progress = BatchProgressCallback(),
    RunningSumsCache* kept = nullptr) const
  {
    if (!this->Shift || !request.AddPolynomialShift)
    {
      return BatchScheduler<DIM>(*this, points, request, sink, progress, kept).Run();
    }
    // The walks (and any kept sums) are w's; the sink gets u's numbers.
    // Points outside the closed boundary walk from NaN: NaN answers.
    std::vector<std::array<double, 3>> inside(points);
    std::vector<unsigned char> outside(points.size(), 0);
    ParallelForWithProgress(points.size(), request.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
        for (std::size_t i = begin; i < end; ++i)
        {
          Vec<DIM> x;
          if (!ProbeStartPoint<DIM>(points[i].data(), x))
          {
            continue;
          }
          if (!InsideClosedMesh<DIM>(*this->Shape, x))
          {
            outside[i] = 1;
            inside[i].fill(std::numeric_limits<double>::quiet_NaN());
          }
        }
      },
      nullptr, 0.1, 256);
    const SampleLayout layout = this->Layout(request);
    const PointSink shifted = [&](std::size_t i, const RunningStatistics& stats,
                                const WalkCounters& counters, DerivativeStatus status) {
      RunningStatistics u = stats;
      this->AddShift(points[i], layout, request.Derivatives, u);
      sink(i, u, counters, status);
    };
    BatchSummary summary = BatchScheduler<DIM>(*this, inside, request, shifted, progress, kept).Run();
    for (unsigned char o : outside)
    {
      summary.PointsOutsideShift += o;
    }
    return summary;
  }

  // Estimate, with every point's means and variances collected.
  BatchEstimates EstimateAll(const std::vector<std::array<double, 3>>& points,
    const BatchRequest& request,
    const BatchProgressCallback& progress = BatchProgressCallback(),
    RunningSumsCache* kept = nullptr) const
  {
    BatchEstimates out;
    out.Points = points.size();
    const std::size_t size = static_cast<std::size_t>(this->Layout(request).Size);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.Means.assign(out.Points * size, nan);
    out.Variances.assign(out.Points * size, nan);
    out.Counters.assign(out.Points, WalkCounters());
    out.Status.assign(out.Points, DerivativeStatus::Unavailable);
    out.Finished.assign(out.Points, 0);
    out.ErrorBars.assign(out.Points, ErrorBarCheck());
    const SampleLayout layout = this->Layout(request);
    out.Summary = this->Estimate(points, request,
      [this, &out, &layout, size](std::size_t i, const RunningStatistics& stats,
        const WalkCounters& counters, DerivativeStatus status) {
        for (std::size_t s = 0; s < size; ++s)
        {
          out.Means[i * size + s] = stats.GetMean(static_cast<int>(s));
          out.Variances[i * size + s] = stats.VarianceOfMean(static_cast<int>(s));
        }
        out.Counters[i] = counters;
        out.Status[i] = status;
        out.Finished[i] = 1;
        out.ErrorBars[i] = this->ErrorBar(stats, counters, layout, status);
      },
      progress, kept);
    return out;
  }

private:
  // The varying walk's settings from the problem's (its ε, step limit, far
  // sphere and splitting), with or without the gradient.
  VaryingCoefficientSettings VaryingSettings(bool gradient) const
  {
    VaryingCoefficientSettings s;
    s.Epsilon = this->Walk.Epsilon;
    s.MaxSteps = this->Walk.MaxSteps;
    s.EscapeRadiusFactor = this->Walk.EscapeRadiusFactor;
    s.Gradient = gradient;
    s.NearBoundarySplitting = this->Walk.NearBoundarySplitting;
    return s;
  }

  std::unique_ptr<VolumeSource<DIM>> MakeVolume() const
  {
    return this->Sources && this->Sources->MakeVolume
      ? this->Sources->MakeVolume(this->DomainBox().Diagonal())
      : nullptr;
  }

  // The box of the whole boundary (both parts of a mixed one).
  BoundingBox<DIM> DomainBox() const
  {
    return this->Mixed ? this->Mixed->Bounds()
                       : BoundingBox<DIM>(this->Shape->BoundsMin(), this->Shape->BoundsMax());
  }

  ConcentratedSourceSet<DIM> Concentrated() const
  {
    ConcentratedSourceSet<DIM> set =
      this->Sources ? this->Sources->Concentrated() : ConcentratedSourceSet<DIM>();
    set.VolumeDensity = this->Density.get();
    return set;
  }

  // Automatic source sampling: source-density sampling where |f| is
  // concentrated (half of the map's mass in at most kNarrowSourceShare of
  // its cells: a narrow source, which Green's-function samples find only in
  // rare walks that each carry much of the value, so that a few hundred
  // walks misreport their spread), Green's-function sampling elsewhere,
  // where the map's second sample per step would cost without helping.
  static constexpr double kNarrowSourceShare = 0.02;
  void ResolveSourceSampling()
  {
    if (this->Walk.Sampling != SourceSampling::Automatic)
    {
      return;
    }
    this->Walk.Sampling = SourceSampling::GreensFunction;
    std::shared_ptr<const SourceDensityMap<DIM>> map = this->MakeSourceDensityMap();
    this->KeepSampledSourceRange(map.get());
    if (map && !map->Empty() && map->HalfMassCellShare() <= kNarrowSourceShare)
    {
      this->Walk.Sampling = SourceSampling::SourceDensity;
      this->Density = std::move(map);
    }
  }

  // f's range over a source map's samples (SourceDensityMap::SampledRange),
  // for the error bars' bounds where the source states none (SteadyRange);
  // empty where a component's is unknown.
  void KeepSampledSourceRange(const SourceDensityMap<DIM>* map)
  {
    this->SampledSourceLow.clear();
    this->SampledSourceHigh.clear();
    const int nc = map ? this->Shape->Components() : 0;
    for (int c = 0; c < nc; ++c)
    {
      double low = 0.0, high = 0.0;
      if (!map->SampledRange(c, low, high))
      {
        this->SampledSourceLow.clear();
        this->SampledSourceHigh.clear();
        return;
      }
      this->SampledSourceLow.push_back(low);
      this->SampledSourceHigh.push_back(high);
    }
  }

  // Whether a volume source leaves some component's range unstated.
  bool SourceStatesNoRange() const
  {
    const std::unique_ptr<VolumeSource<DIM>> volume = this->MakeVolume();
    double low = 0.0, high = 0.0;
    for (int c = 0; volume && c < this->Shape->Components(); ++c)
    {
      if (!volume->ValueBounds(c, low, high))
      {
        return true;
      }
    }
    return false;
  }

  // Source-density sampling's map, unless Automatic built it already.
  void BuildSourceDensity()
  {
    if (this->Walk.Sampling == SourceSampling::SourceDensity && !this->Density)
    {
      this->Density = this->MakeSourceDensityMap();
    }
  }

  // The map of |f| (SourceDensityMap.h), over the source's support within
  // the boundary's box (walks inside the domain never leave it), or over the
  // support alone when they do not meet (exterior problems), or the
  // boundary's box for an unbounded support; null without a volume source.
  std::shared_ptr<const SourceDensityMap<DIM>> MakeSourceDensityMap() const
  {
    if (!this->Sources || !this->Sources->MakeVolume ||
      !WalkOnSpheresEstimator<DIM>::UsesSources(this->Walk.Problem))
    {
      return nullptr;
    }
    auto volume = this->MakeVolume();
    if (!volume)
    {
      return nullptr;
    }
    const BoundingBox<DIM> domain = this->DomainBox();
    BoundingBox<DIM> box = domain;
    Vec<DIM> lo, hi;
    if (volume->SupportBounds(lo, hi))
    {
      const BoundingBox<DIM> inside(lo.cwiseMax(domain.Min), hi.cwiseMin(domain.Max));
      box = inside.IsEmpty() ? BoundingBox<DIM>(lo, hi) : inside;
    }
    auto map = std::make_shared<SourceDensityMap<DIM>>();
    map->Build(*volume, this->Shape->Components(), box);
    return map;
  }


  // The boundary walks end on: the whole one, or a mixed one's Dirichlet
  // part (its Neumann part when it has none), which gives the values'
  // components; Mixed is set for walk on stars.
  std::shared_ptr<const Boundary<DIM>> Shape;
  std::shared_ptr<const MixedBoundary<DIM>> Mixed;
  WalkSettings Walk;
  std::shared_ptr<const SourceSet<DIM>> Sources;
  std::shared_ptr<const PolynomialShift<DIM>> Shift;
  std::shared_ptr<const CoefficientModel<DIM>> Coefficients;
  std::shared_ptr<const SourceDensityMap<DIM>> Density;
  std::vector<double> SampledSourceLow, SampledSourceHigh; // KeepSampledSourceRange
  std::shared_ptr<const ScreenedGuide<DIM>> Guide; // guided screened steps, or null
  bool GuideLeadsMildly = false;                    // chosen by LeadingGuide
  std::shared_ptr<const PeakGuide<DIM>> Peak;      // steps toward the data's peak, or null
  bool ConstantData = false; // constant boundary values and no sources
  ErrorBarRule BoundedWalks;  // with the walk values' bounds, where known
};
} // namespace gridfree

#endif
