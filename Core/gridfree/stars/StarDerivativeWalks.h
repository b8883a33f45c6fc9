// The solution's derivatives with mixed conditions: the first ball of the
// derivative estimator (DerivativeWalkOnSpheres.h) followed by walk on stars
// (WalkOnStars.h).
//
// The first ball B0 = B(x0, R0) must lie where the equation holds, so R0 is
// the distance to the whole boundary, Dirichlet and reflecting parts alike
// (not the star radius: a star may reach past the Neumann part's
// silhouettes, a ball may not). Inside B0 the ball's mean-value identities
// hold whatever the conditions beyond it (Documentation/WalkOnStars.md §8),
// so the value, gradient and Hessian weights, the source integrals and the
// control variates are those of DerivativeWalkOnSpheres.h, and only the walk
// that returns û(x1) from x1 on ∂B0 changes: a walk on stars, unbiased for
// u(x1) under Dirichlet, Neumann and Robin conditions.
//
// Points closer than ε to either part take their derivatives one-sidedly
// from a point moved into the domain (DerivativeStatus::OneSided), along the
// direction from the closest point, or along the inward normal for a point
// on the boundary (the mesh's outward orientation, which the reflecting part
// needs anyway: MixedBoundary.h). The screened walk keeps no weight slot, as
// in value batches: walk on stars' weights also fall at Neumann and Robin hits.
#ifndef GRIDFREE_STARS_STAR_DERIVATIVE_WALKS_H
#define GRIDFREE_STARS_STAR_DERIVATIVE_WALKS_H

#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/stars/MixedBoundary.h>
#include <gridfree/stars/WalkOnStars.h>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace gridfree
{
// Walk on stars as what continues from the first ball.
template <int DIM>
class StarWalkContinuation
{
public:
  using BoundaryType = MixedBoundary<DIM>;
  static constexpr bool kWeightSlot = false;

  StarWalkContinuation(const MixedBoundary<DIM>& boundary, const WalkSettings& settings,
    VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
    : Geometry(boundary)
    , Walker(boundary, settings, volume, concentrated)
  {
  }

  int Components() const { return this->Geometry.Components(); }
  double Diagonal() const { return this->Geometry.Diagonal(); }

  // Distance to the whole boundary: the largest ball about x in the domain.
  double Distance(const Vec<DIM>& x) const
  {
    const MixedBoundary<DIM>& b = this->Geometry;
    const double infinity = std::numeric_limits<double>::infinity();
    return std::min(b.HasDirichlet() ? b.Dirichlet().Distance(x) : infinity,
      b.HasReflecting() ? b.Reflecting().Distance(x) : infinity);
  }

  // The closest point of either part and the inward normal there.
  bool ClosestPoint(const Vec<DIM>& x, Vec<DIM>& point, Vec<DIM>& inward) const
  {
    const MixedBoundary<DIM>& b = this->Geometry;
    ClosestPointResult<DIM> toDirichlet, toReflecting;
    if (b.HasDirichlet())
    {
      toDirichlet = b.Dirichlet().ClosestPoint(x);
    }
    if (b.HasReflecting())
    {
      toReflecting = b.Reflecting().ClosestPoint(x);
    }
    const bool reflecting = toReflecting.primitive >= 0 &&
      (toDirichlet.primitive < 0 || toReflecting.distance < toDirichlet.distance);
    if (reflecting)
    {
      point = toReflecting.point;
      inward = -b.OutwardNormal(toReflecting.primitive);
      return true;
    }
    if (toDirichlet.primitive < 0)
    {
      return false;
    }
    point = toDirichlet.point;
    inward = -b.Dirichlet().Normal(toDirichlet);
    return true;
  }

  // g at the closest point of the Dirichlet part (0 without one): the
  // control variates' first constant, any constant being unbiased.
  void Pilot(const Vec<DIM>& x, double* out) const
  {
    const MixedBoundary<DIM>& b = this->Geometry;
    if (b.HasDirichlet())
    {
      b.Dirichlet().Evaluate(x, b.Dirichlet().ClosestPoint(x), out);
    }
    else
    {
      std::fill(out, out + b.Components(), 0.0);
    }
  }

  // Walk on stars has its own escape sphere and exterior returns.
  double EscapeRadius(const Vec<DIM>&) const { return 0.0; }
  // The walks of a point continue on the side of the boundary its first
  // ball's centre lies on (WalkOnStarsEstimator::ChooseSide: the exterior
  // for a point outside, when the problem answers both sides). x1 on the
  // first ball is on that side too: the ball holds no boundary.
  void StartFrom(const Vec<DIM>& centre) { this->Walker.ChooseSide(centre); }
  WalkEnd Walk(const Vec<DIM>& x, double, RandomStream& rng, double* sample, int& steps,
    std::uint64_t&, double splitScale = 0.0)
  {
    return this->Walker.Walk(x, rng, sample, steps, splitScale);
  }
  double LastWeight() const { return 1.0; }
  double FirstStepWeight() const { return 1.0; }
  bool SourceSupportIsBounded() const { return this->Walker.SourceSupportIsBounded(); }
  std::uint64_t BackFaceHits() const { return this->Walker.BackFaceHits(); }

private:
  const MixedBoundary<DIM>& Geometry;
  WalkOnStarsEstimator<DIM> Walker;
};

template <int DIM>
using StarDerivativeWalks = DerivativeWalkOnSpheres<DIM, StarWalkContinuation<DIM>>;
} // namespace gridfree

#endif
