// Walk on stars (Sawhney, Miller, Gkioulekas & Crane 2023), with Robin
// conditions as in "Walkin' Robin" (Miller, Sawhney, Crane & Gkioulekas
// 2024), for
//
//   Laplace          Δu = 0
//   Poisson          Δu = f
//   ScreenedPoisson  Δu − c·u = f   (c > 0)
//
// with u = g on the Dirichlet part of the boundary and ∂u/∂n + μu = h on the
// reflecting part (n the outward normal; μ = 0: Neumann): MixedBoundary.h. Documentation/
// WalkOnStars.md has the derivation, the equation numbers cited here and
// what was checked against the authors' library.
//
// One step from x_k (on the Neumann part or inside the domain), with ball
// Green's function G of radius R (GreensFunctions.h) and α = 1/2 on the
// Neumann part, 1 inside (WoSt-2):
//
//   α u(x_k) = E[Q(r) u(x_{k+1})] + ∫_{∂St ∩ Γ_N} G h dz − ∫_{St} G f dy.
//
// - R = min(distance to the Dirichlet part, distance to the closest
//   silhouette of the Neumann part); below that the star St(x_k, R), the part
//   of the ball seen from x_k, is star-shaped (WoSt-1). A silhouette closer
//   than 0.99·ε is ignored and R = ε (a small bias near reflex corners, where
//   walks would otherwise take ever smaller steps).
// - Direction v uniform on the sphere; on the Neumann part, in the inward
//   hemisphere (density 2/|S|, which cancels 1/α).
// - x_{k+1}: the first Neumann point on the ray within R, else x_k + R v,
//   x_k taken where the ray starts (moved 1e-9 of the boundary's diagonal
//   off the Neumann part it lies on).
//   The walk's weight is multiplied by Q(r) (StarKernels.h, WoSt-4): 1 for
//   Δ, the screened kernel's ratio for Δ − c.
// - The flux term: one point z on the Neumann part in the ball
//   (ReflectingBoundarySampler.h), kept if x_k sees it, weight G(|z − x_k|)
//   h(z) / (α pdf(z)) (WoSt-3). In 3D, on the Neumann part, z is drawn
//   either by area over the hierarchy or in the plane of x_k's triangle with
//   density ∝ 1/r (SampleInPlane; kept where the plane holds Neumann
//   triangles; half the draws on a large flat patch, fewer on a small one),
//   pdf the mixture's: the weight then stays bounded where G ~ 1/r on that
//   plane, and so does its variance.
// - The source term: the walk-on-spheres sampler of the ball (SourceTerms.h)
//   with every sample y outside St (hidden from x_k, or behind the Neumann
//   part x_k lies on) given weight 0, the others 1/α; minus sign as in
//   FORMULAS.md §2. Under source-density sampling R is also capped where
//   the walker stands in a strong source (SourceIntegrator::SourceStepCap),
//   as walk on spheres caps its balls.
// - On a Robin primitive (μ > 0) the ray weight is Q(r) − μ|S| G(r)
//   r^{n−1}/(n·v) (WoSt-7), and R is also bounded so that this stays >= 0
//   (MixedBoundary::RobinRadius).
// A walk ends within ε of the Dirichlet part and takes g at its closest
// point there. With WalkSettings::NearBoundarySplitting, a walk whose
// distance to the Dirichlet part grows to twice the largest it had goes on
// as two branches of half its weight (NearBoundarySplitting.h), each
// walked in turn on the same random stream.
// A screened walk whose weight falls below kRouletteWeight survives with
// probability weight / kRouletteWeight and then carries kRouletteWeight
// (unbiased): with no Dirichlet part that is how walks end.
// Walks with Robin primitives play it too, their weights falling at Robin
// hits; a branch plays it against its share of the walk (1/2 per split).
#ifndef GRIDFREE_STARS_WALK_ON_STARS_H
#define GRIDFREE_STARS_WALK_ON_STARS_H

#include <gridfree/estimators/EquationPolicies.h>
#include <gridfree/estimators/ExteriorReturn.h>
#include <gridfree/estimators/NearBoundarySplitting.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/sampling/BallSampling.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/stars/MixedBoundary.h>
#include <gridfree/stars/StarKernels.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gridfree
{
// Whether an exterior domain takes the equation: Laplace (which reads no
// source), or screened Poisson without sources; not the Poisson equation,
// whose sources outside have no bound.
inline bool ExteriorTakes(const WalkSettings& settings, bool sources)
{
  return settings.Problem == Equation::Laplace ||
    (settings.Problem == Equation::ScreenedPoisson && !sources);
}

// Whether walks on `boundary` answer start points on both of its sides
// (WalkSettings::MixedBothSides): the exterior takes the Laplace equation,
// or the screened one without sources (ExteriorTakes).
template <int DIM>
bool AnswersBothSides(const MixedBoundary<DIM>& boundary, const WalkSettings& settings, bool sources)
{
  return settings.MixedBothSides && ExteriorTakes(settings, sources) && !boundary.IsExterior();
}

template <int DIM>
class WalkOnStarsEstimator
{
public:
  // Weight below which screened walks play Russian roulette.
  static constexpr double kRouletteWeight = 0.1;
  // Fraction of the distance to the closest silhouette a star may reach.
  static constexpr double kSilhouetteShrink = 0.99;

  WalkOnStarsEstimator(const MixedBoundary<DIM>& boundary, const WalkSettings& settings,
    VolumeSource<DIM>* volume = nullptr,
    const ConcentratedSourceSet<DIM>& concentrated = ConcentratedSourceSet<DIM>())
    : Given(boundary)
    , Geometry(&boundary)
    , BothSides(AnswersBothSides(boundary, settings, volume != nullptr || !concentrated.Empty()))
    , Settings(settings)
    , NumberOfComponents(boundary.Components())
    , Sources(boundary.Components(), settings.Sampling,
        settings.Problem == Equation::Laplace ? nullptr : volume,
        settings.Problem == Equation::Laplace ? ConcentratedSourceSet<DIM>() : concentrated)
    , Values(boundary.Components())
    , Inner(boundary.Components())
    , Accumulated(boundary.Components())
    , Sample(boundary.Components())
  {
    if (settings.Problem == Equation::Biharmonic)
    {
      throw std::invalid_argument("walk on stars solves Laplace, Poisson and screened Poisson "
                                  "equations, not the biharmonic one");
    }
    const bool screened = settings.Problem == Equation::ScreenedPoisson;
    if (screened && !(settings.ScreeningCoefficient > 0.0))
    {
      throw std::invalid_argument("the screening coefficient must be positive");
    }
    if (!boundary.HasDirichlet() && !screened && !boundary.HasRobin())
    {
      throw std::invalid_argument(
        "a boundary without a Dirichlet part needs screening or a Robin part: with Neumann "
        "conditions alone the solution of a Laplace or Poisson equation is not unique");
    }
    if (boundary.IsExterior() && !ExteriorTakes(settings, volume != nullptr || !concentrated.Empty()))
    {
      throw std::invalid_argument("exterior mixed problems solve the Laplace equation, or the "
                                  "screened Poisson equation without sources (yet)");
    }
    const double diagonal = std::max(boundary.Diagonal(), settings.Epsilon);
    this->Center = boundary.Center();
    this->EnclosingRadius = 0.5 * diagonal * (1.0 + 1e-9);
    this->MaxRadius = diagonal;
    this->EscapeRadius = std::max(settings.EscapeRadiusFactor, 1.0) * diagonal;
    this->Offset = 1e-9 * diagonal;
    this->MinDistance = 1e-12 * diagonal;
  }

  int OutputComponents() const { return this->NumberOfComponents; }

  // Walks stay in the domain, so any source is only ever read inside it.
  bool SourceSupportIsBounded() const { return true; }

  // Rays that met the Neumann part from outside, over this estimator's life:
  // nonzero means the Neumann part is inconsistently oriented or leaks.
  std::uint64_t BackFaceHits() const { return this->BackHits; }

  // The domain the next walks run in: the given one, or, when this
  // estimator answers both sides (AnswersBothSides), the one on the other
  // side of the boundary if x is not inside the given one (ray parity,
  // MixedBoundary::Inside). A point's walks all start on its side, so this
  // is asked once per point, not per walk.
  void ChooseSide(const Vec<DIM>& x)
  {
    this->Geometry = this->BothSides && !this->Given.Inside(x) ? &this->Given.OtherSide()
                                                                : &this->Given;
  }

  // As WalkOnSpheresEstimator::EstimatePoint: walks firstWalk ..
  // firstWalk + walks − 1 from the probe point, into stats and counters.
  template <class Statistics>
  void EstimatePoint(const double probeXYZ[3], std::uint64_t seed, std::uint64_t firstWalk,
    int walks, Statistics& stats, WalkCounters& counters)
  {
    Vec<DIM> x0;
    if (this->BothSides && ProbeStartPoint<DIM>(probeXYZ, x0))
    {
      this->ChooseSide(x0);
    }
    RunPointWalks<DIM>(probeXYZ, seed, firstWalk, walks, this->Sample, stats, counters,
      [this](const Vec<DIM>& x0, int, RandomStream& rng, int& steps) {
        return this->Walk(x0, rng, this->Sample.data(), steps);
      });
  }

  // One walk from x0 (in the domain ChooseSide chose: the given one unless
  // it was asked); writes OutputComponents() numbers. `splitScale` as for
  // walk on spheres (NearBoundarySplit::First).
  WalkEnd Walk(
    const Vec<DIM>& x0, RandomStream& rng, double* sample, int& steps, double splitScale = 0.0)
  {
    if (this->Settings.Problem == Equation::ScreenedPoisson)
    {
      return this->WalkWith(x0, rng, sample, steps, splitScale,
        equations::Screened<DIM>{ this->Settings.ScreeningCoefficient });
    }
    return this->WalkWith(x0, rng, sample, steps, splitScale, equations::Harmonic<DIM>{});
  }

private:
  // Whether x sees y: not behind the Neumann part x lies on (normal n), and
  // no Neumann primitive between them. `origin` is x moved off that part.
  bool Sees(const Vec<DIM>& x, const Vec<DIM>& origin, bool onNeumann, const Vec<DIM>& n,
    const Vec<DIM>& y) const
  {
    if (onNeumann && (y - x).dot(n) > 1e-7 * (y - x).norm())
    {
      return false;
    }
    return !this->Geometry->Reflecting().Hierarchy().Occluded(origin, y - origin, 1.0, 0.0);
  }

  // A walk's branch (NearBoundarySplitting): where it is, on which
  // Neumann primitive (if any) and with what normal, its weight and its
  // share of the walk (1/2 per split: roulette plays on weight/share), the
  // reach at which it splits next, how many splits it has left, its own
  // steps and closest-point hint.
  struct Branch
  {
    Vec<DIM> X;
    double Weight;
    double Share;
    bool OnNeumann;
    std::int64_t OnPrimitive;
    Vec<DIM> N;
    double NextSplit;
    int SplitsLeft;
    int Steps;
    typename Boundary<DIM>::StepHint Hint;
  };

  template <class Policy>
  WalkEnd WalkWith(
    const Vec<DIM>& x0, RandomStream& rng, double* sample, int& steps, double splitScale,
    const Policy& equation)
  {
    constexpr bool screened = Policy::WeightsSteps;
    const WalkSettings& s = this->Settings;
    const MixedBoundary<DIM>& b = *this->Geometry;
    const bool hasD = b.HasDirichlet();
    const bool hasN = b.HasReflecting();
    const bool robin = b.HasRobin();
    const bool flux = hasN && b.HasFlux(); // else the flux term is 0: not sampled
    const int nc = this->NumberOfComponents;
    const double sqrtC = std::sqrt(equation.ScreeningCoefficient());
    const double escape2 = this->EscapeRadius * this->EscapeRadius;
    std::fill(this->Accumulated.begin(), this->Accumulated.end(), 0.0);
    WalkEnd end = WalkEnd::Boundary;
    const bool exterior = b.IsExterior();
    const double far = s.FarRadiusFactor * this->EnclosingRadius;
    // Splitting judges a walker by its distance to the Dirichlet part (the
    // walks' only end besides roulette): none without one.
    const double splitCeiling = NearBoundarySplit::Ceiling(
      s.NearBoundarySplitting && hasD, b.Diagonal(), equation.ScreeningCoefficient());
    steps = 0;
    // This walk's branches still to walk (the first, then those split off),
    // each on the same random stream in turn: the walk's numbers do not
    // depend on threads.
    this->Pending.clear();
    this->Pending.push_back(Branch{ x0, 1.0, 1.0, false, -1, Vec<DIM>::Zero(), 0.0,
      NearBoundarySplit::kMaxSplits, 0, {} });
    int branches = 1;
    while (!this->Pending.empty())
    {
      Branch branch = this->Pending.back();
      this->Pending.pop_back();
      Vec<DIM> x = branch.X;
      double weight = branch.Weight;
      bool onNeumann = branch.OnNeumann;
      std::int64_t onPrimitive = branch.OnPrimitive; // the Neumann primitive x lies on
      Vec<DIM> n = branch.N;
      WalkEnd branchEnd = WalkEnd::Boundary;
      bool hasValue = true;
      auto& hint = branch.Hint;
      for (;; ++branch.Steps, ++steps)
      {
        if (!screened && exterior && (x - this->Center).squaredNorm() > far * far)
        {
          // Far outside (exterior domain, Laplace): back to the sphere about
          // the boundary with the probability Brownian motion ever returns,
          // at its hitting point, or gone for good (u → 0 at infinity;
          // ExteriorReturn.h).
          const double r = (x - this->Center).norm();
          if (rng.NextDouble() >= ReturnProbability<DIM>(r, this->EnclosingRadius))
          {
            branchEnd = WalkEnd::Terminated;
            hasValue = false;
            break;
          }
          x = SampleExteriorReturn<DIM>(x, this->Center, this->EnclosingRadius, rng);
          onNeumann = false;
        }
        if (!((x - this->Center).squaredNorm() <= escape2))
        {
          branchEnd = WalkEnd::Escaped;
          hasValue = false;
          break;
        }
        const double toDirichlet =
          hasD ? b.Dirichlet().StepRadius(x, s.Epsilon, &hint) : std::numeric_limits<double>::infinity();
        if (!(toDirichlet >= s.Epsilon))
        {
          break;
        }
        if (branch.Steps >= s.MaxSteps)
        {
          branchEnd = WalkEnd::MaxSteps;
          break;
        }
        // A branch whose distance to the Dirichlet part grows to twice the
        // largest it had goes on as two of half its weight (as walk on
        // spheres' do: NearBoundarySplitting).
        NearBoundarySplit::AtStep(toDirichlet, steps == 0, splitScale, splitCeiling,
          branch.NextSplit, branch.SplitsLeft, branches, [&] {
            weight *= 0.5;
            branch.Share *= 0.5;
            this->Pending.push_back(Branch{ x, weight, branch.Share, onNeumann, onPrimitive, n,
              branch.NextSplit, branch.SplitsLeft, branch.Steps, hint });
          });
        double radius = std::min(toDirichlet, this->MaxRadius);
        if (hasN)
        {
          const double toSilhouette = b.Silhouettes().ClosestDistance(x, radius);
          if (toSilhouette < radius)
          {
            radius = std::max(s.Epsilon, kSilhouetteShrink * toSilhouette);
          }
          if (robin)
          {
            radius = std::max(s.Epsilon, std::min(radius, b.RobinRadius(x, radius)));
          }
        }
        if (this->Sources.Active())
        {
          // Smaller stars where the walker stands in a strong source under
          // source-density sampling (SourceIntegrator::SourceStepCap): a
          // smaller star is as unbiased, and it keeps one map sample near
          // the walker from outweighing the rest.
          radius = std::max(s.Epsilon, std::min(radius, this->Sources.SourceStepCap(x, b.Diagonal())));
        }
        const auto green = equation.Green(radius);
        const double alphaInverse = onNeumann ? 2.0 : 1.0;

        Vec<DIM> v = SampleUnitSphere<DIM>(rng);
        if (onNeumann && v.dot(n) > 0.0)
        {
          v = -v; // the inward hemisphere
        }
        const Vec<DIM> origin = onNeumann ? Vec<DIM>(x - this->Offset * n) : x;

        if (this->Sources.Active())
        {
          // −∫_{St} f G (WoSt-2; FORMULAS.md §2 for the sign).
          std::fill(this->Inner.begin(), this->Inner.end(), 0.0);
          this->Sources.Accumulate(x, green, rng, this->Inner.data(),
            [&](const Vec<DIM>& y) {
              return !hasN || this->Sees(x, origin, onNeumann, n, y) ? alphaInverse : 0.0;
            });
          for (int c = 0; c < nc; ++c)
          {
            this->Accumulated[c] -= weight * this->Inner[c];
          }
        }

        if (hasN)
        {
          if (flux)
          {
            this->AddFluxTerm(
              x, origin, onNeumann, n, onPrimitive, radius, green, alphaInverse * weight, rng);
          }
          const RayHit<DIM> hit = b.Reflecting().Hierarchy().Intersect(origin, v, radius);
          if (hit.Hit() && hit.t < radius)
          {
            Vec<DIM> normal = b.OutwardNormal(hit.primitive);
            if (normal.dot(v) < 0.0)
            {
              // Met from outside: keep the walk on the side it came from
              // (an insulating sheet's other side is no fault).
              this->BackHits += b.IsTwoSided(hit.primitive) ? 0 : 1;
              normal = -normal;
            }
            const double r = (hit.point - x).norm();
            double q = 1.0;
            if constexpr (screened)
            {
              q = ScreenedRayWeight<DIM>(r, radius, sqrtC);
            }
            const double mu = b.RobinCoefficient(hit.primitive);
            if (mu > 0.0)
            {
              // WoSt-7: the Robin part's −∫ μ G u joins the ray weight.
              const double cosine = std::max(normal.dot(v), 1e-300);
              q -= mu * UnitSphereArea<DIM>() * green.Value(std::max(r, this->MinDistance)) *
                (DIM == 2 ? r : r * r) / cosine;
            }
            weight *= q;
            x = hit.point;
            n = normal;
            onNeumann = true;
            onPrimitive = hit.primitive;
          }
          else
          {
            // From the point the ray was traced from: from x itself, a ray
            // that grazes a neighbouring primitive may cross it within the
            // radius where the traced one, Offset below, crosses beyond it,
            // and the walk would leave the domain (seen as back-face hits).
            x = origin + radius * v;
            onNeumann = false;
            if constexpr (screened)
            {
              weight *= green.BoundaryWeight();
            }
          }
        }
        else
        {
          x += radius * v;
          if constexpr (screened)
          {
            weight *= green.BoundaryWeight();
          }
        }

        if (screened || robin)
        {
          // Roulette on |weight| against the branch's share of the walk
          // (1 unless it split): a Robin weight may fall below 0 where the
          // radius floor ε overrides RobinRadius.
          const double magnitude = std::abs(weight);
          const double least = kRouletteWeight * branch.Share;
          if (magnitude < least)
          {
            if (rng.NextDouble() * least >= magnitude)
            {
              branchEnd = WalkEnd::Terminated;
              hasValue = false;
              break;
            }
            weight = weight < 0.0 ? -least : least;
          }
        }
      }

      end = MoreSevereEnd(end, branchEnd);
      if (hasValue && hasD)
      {
        b.Dirichlet().Evaluate(x, b.Dirichlet().ClosestPoint(x, hint), this->Values.data());
        for (int c = 0; c < nc; ++c)
        {
          this->Accumulated[c] += weight * this->Values[c];
        }
      }
    }
    for (int c = 0; c < nc; ++c)
    {
      sample[c] = this->Accumulated[c];
    }
    return end;
  }

  // Adds factor · G(|z − x|) h(z) / pdf(z) for one point z of the Neumann
  // part in the ball that x sees (WoSt-3); nothing when none is drawn. On
  // the Neumann part in 3D (x on primitive `onPrimitive`), z comes from a
  // mixture of the hierarchy's sampling and SampleInPlane in that
  // primitive's plane (PlaneShare: half on a large flat patch, less on a
  // small one), and pdf is the mixture's (one-sample, balance heuristic).
  // The flux is taken along the domain's outward normal (FluxSign: an
  // exterior domain's is opposite to the mesh's on Neumann primitives).
  template <class Green>
  void AddFluxTerm(const Vec<DIM>& x, const Vec<DIM>& origin, bool onNeumann, const Vec<DIM>& n,
    std::int64_t onPrimitive, double radius, const Green& green, double factor, RandomStream& rng)
  {
    const MixedBoundary<DIM>& b = *this->Geometry;
    const ReflectingBoundarySampler<DIM>& sampler = b.FluxSampler();
    const bool mixture = DIM == 3 && onNeumann && onPrimitive >= 0;
    BoundarySample<DIM> z;
    bool near = false;
    double share = 0.0; // of the draws made in x's plane
    if (mixture)
    {
      share = sampler.PlaneShare(onPrimitive, radius);
      near = rng.NextDouble() < share;
    }
    if (near)
    {
      if constexpr (DIM == 3)
      {
        if (!this->SampleInPlane(x, onPrimitive, radius, rng, z))
        {
          return;
        }
      }
    }
    else if (!sampler.Sample(x, radius, rng, z))
    {
      return;
    }
    const double r = (z.Point - x).norm();
    if (!(r < radius) || b.IsTwoSided(z.Primitive))
    {
      return; // (no flux crosses an insulating sheet)
    }
    if (mixture)
    {
      const double byArea = near ? sampler.Pdf(x, radius, z.Primitive) : z.Pdf;
      const double byDistance = this->Coplanar(z.Primitive, onPrimitive, x)
        ? ReflectingBoundarySampler<DIM>::NearPdf(radius, r)
        : 0.0;
      z.Pdf = (1.0 - share) * byArea + share * byDistance;
    }
    // Test visibility to a point just inside the domain off z, so that the
    // primitive z lies on does not hide it.
    const Vec<DIM> target = z.Point - this->Offset * b.OutwardNormal(z.Primitive);
    if (!this->Sees(x, origin, onNeumann, n, target))
    {
      return;
    }
    ClosestPointResult<DIM> at;
    at.point = z.Point;
    at.distance = 0.0;
    at.primitive = z.Primitive;
    at.barycentric = z.Barycentric;
    b.Reflecting().Evaluate(at, this->Inner.data());
    const double w =
      b.FluxSign(z.Primitive) * factor * green.Value(std::max(r, this->MinDistance)) / z.Pdf;
    for (int c = 0; c < this->NumberOfComponents; ++c)
    {
      this->Accumulated[c] += w * this->Inner[c];
    }
  }

  // A point of the Neumann part in the plane of primitive `own` (x on it),
  // density 1/(2π R r) in that plane: kept where a Neumann triangle in the
  // same plane holds it, z then on that triangle.
  bool SampleInPlane(const Vec<DIM>& x, std::int64_t own, double radius, RandomStream& rng,
    BoundarySample<DIM>& z) const
  {
    Vec<DIM> y;
    const MixedBoundary<DIM>& b = *this->Geometry;
    if (!b.FluxSampler().SampleInPlane(x, own, radius, rng, y))
    {
      return false;
    }
    const ClosestPointResult<DIM> hit = b.Reflecting().ClosestPoint(y);
    if (hit.primitive < 0 || !(hit.distance <= this->Offset) || !this->Coplanar(hit.primitive, own, x))
    {
      return false;
    }
    z.Point = hit.point;
    z.Primitive = hit.primitive;
    z.Barycentric = hit.barycentric;
    return true;
  }

  // Whether primitive p lies in the plane of primitive `own` through x
  // (within Offset): where SampleInPlane's points may land.
  bool Coplanar(std::int64_t p, std::int64_t own, const Vec<DIM>& x) const
  {
    const MixedBoundary<DIM>& b = *this->Geometry;
    const Vec<DIM>& n = b.OutwardNormal(own);
    return (p == own || b.OutwardNormal(p).dot(n) >= 1.0 - 1e-12) &&
      std::abs((b.FluxSampler().FirstVertex(p) - x).dot(n)) <= this->Offset;
  }

  const MixedBoundary<DIM>& Given;
  const MixedBoundary<DIM>* Geometry; // the domain walks run in (ChooseSide)
  bool BothSides = false;
  WalkSettings Settings;
  int NumberOfComponents;
  SourceIntegrator<DIM> Sources;
  Vec<DIM> Center = Vec<DIM>::Zero();
  double MaxRadius = 0.0;
  double EnclosingRadius = 0.0; // of the sphere about Center holding the boundary
  double EscapeRadius = 0.0;
  double Offset = 0.0;
  double MinDistance = 0.0;
  std::uint64_t BackHits = 0;
  // Scratch: end values, one source or flux evaluation, the running sum, a sample.
  std::vector<double> Values;
  std::vector<double> Inner;
  std::vector<double> Accumulated;
  std::vector<double> Sample;
  std::vector<Branch> Pending;
};
} // namespace gridfree

#endif
