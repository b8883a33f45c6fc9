// A boundary given as the zero set of a function φ (paper Sec. 5.1.3): an
// exact signed distance, a CSG tree of them, or any function with a known
// Lipschitz bound L (Hart 1996). The walk's step radius is |φ(x)| / L, which
// never exceeds the distance to the zero set, so every ball stays inside the
// domain and the estimator keeps its expectation; a non-distance function
// only costs more (smaller) steps.
#ifndef GRIDFREE_IMPLICIT_IMPLICIT_BOUNDARY_H
#define GRIDFREE_IMPLICIT_IMPLICIT_BOUNDARY_H

#include <gridfree/geometry/BoundaryGeometry.h>
#include <gridfree/implicit/SignedDistance.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

namespace gridfree
{
template <int DIM>
class ImplicitBoundaryGeometry final : public BoundaryGeometry<DIM>
{
public:
  // `lipschitz` overrides the function's own bound when positive (a user's
  // setting for a function that cannot know it, e.g. a VTK implicit function).
  explicit ImplicitBoundaryGeometry(
    std::shared_ptr<const SignedDistanceFunction<DIM>> phi, double lipschitz = 0.0)
    : Phi(std::move(phi))
  {
    if (!this->Phi)
    {
      throw std::invalid_argument("implicit boundary: no function");
    }
    this->L = lipschitz > 0.0 ? lipschitz : this->Phi->Lipschitz();
    if (!(this->L > 0.0) || !std::isfinite(this->L))
    {
      throw std::invalid_argument("implicit boundary: the Lipschitz bound must be positive and finite");
    }
    this->Scale = this->L / this->Phi->Lipschitz();
  }

  double Distance(const Vec<DIM>& x) const override
  {
    const double d = std::abs(this->Phi->Value(x)) / this->L;
    // A NaN from the function must not look like a huge safe step.
    return std::isnan(d) ? 0.0 : d;
  }

  // The function's own step bound, |φ|/L_φ relaxed, in units of this L.
  double StepRadius(const Vec<DIM>& x, double relaxation, double epsilon) const override
  {
    if (!this->Phi->CachesBounds())
    {
      return this->Distance(x);
    }
    // StepBound is exact below its epsilon; scaled, below ours.
    const double r = this->Phi->StepBound(x, relaxation, epsilon * this->Scale) / this->Scale;
    return std::isnan(r) ? 0.0 : r;
  }

  // The function's own projection when it has one (meshes, and CSG trees
  // of them where one operand decides). Otherwise it projects x onto the
  // zero set by Newton steps along ∇φ, p ← p − φ ∇φ/|∇φ|²
  // (quadratic convergence near a regular surface). Walks call this within ε
  // of the boundary, where one step is already accurate to O(ε²); a few more
  // are allowed for points farther away (derivative estimators ask at the
  // probe point) and stop as soon as |φ| no longer decreases.
  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const override
  {
    ClosestPointResult<DIM> hit;
    if (this->Phi->Project(x, hit.point, hit.primitive))
    {
      hit.distance = (x - hit.point).norm();
      return hit;
    }
    ImplicitSample s = this->Phi->Sample(x);
    Vec<DIM> p = x;
    for (int iteration = 0; iteration < 8 && s.value != 0.0; ++iteration)
    {
      const Vec<DIM> g = this->Phi->Gradient(p);
      const double g2 = g.squaredNorm();
      if (!(g2 > 0.0) || !std::isfinite(g2))
      {
        break;
      }
      const Vec<DIM> next = p - (s.value / g2) * g;
      const ImplicitSample t = this->Phi->Sample(next);
      if (!(std::abs(t.value) < std::abs(s.value)))
      {
        break;
      }
      p = next;
      s = t;
    }
    hit.point = p;
    hit.distance = (x - p).norm();
    hit.primitive = s.part;
    return hit;
  }

  Vec<DIM> Normal(const ClosestPointResult<DIM>& hit) const override
  {
    const Vec<DIM> g = this->Phi->Gradient(hit.point);
    const double n = g.norm();
    return n > 0.0 && std::isfinite(n) ? Vec<DIM>(g / n) : Vec<DIM>::Zero();
  }

  BoundingBox<DIM> Bounds() const override { return this->Phi->Bounds(); }

  // Inside is where φ < 0 (a signed distance's, a CSG tree's convention).
  bool Encloses(const Vec<DIM>& x) const override { return this->Phi->Value(x) < 0.0; }
  std::int64_t NumberOfParts() const override { return this->Phi->NumberOfParts(); }

  double Lipschitz() const { return this->L; }
  const SignedDistanceFunction<DIM>& Function() const { return *this->Phi; }

private:
  std::shared_ptr<const SignedDistanceFunction<DIM>> Phi;
  double L = 1.0;
  // L / L_φ: a step bound of φ (in units of |φ|/L_φ) divided by it is one in
  // units of |φ|/L.
  double Scale = 1.0;
};
} // namespace gridfree

#endif
