// Implicit boundaries: the zero set of a function φ, negative inside.
//
// Sphere tracing (Hart 1996) and walk on spheres (paper Sec. 5.1.3) need
// only one property of φ: if |φ(x) − φ(y)| ≤ L |x − y| everywhere (a
// Lipschitz bound L), then the ball of radius |φ(x)|/L around x holds no
// point of the zero set, because φ cannot climb from φ(x) to 0 faster. An
// exact signed distance has L = 1 and gives the largest such ball; any other
// function is safe only with a true L, which is why L is part of the
// interface and never guessed.
#ifndef GRIDFREE_IMPLICIT_SIGNED_DISTANCE_H
#define GRIDFREE_IMPLICIT_SIGNED_DISTANCE_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gridfree
{
// φ(x) and which part of a composite function decided it (a CSG leaf).
struct ImplicitSample
{
  double value = 0.0;
  std::int64_t part = 0;
};

// An interval that holds φ(x): Low ≤ φ(x) ≤ High.
struct ImplicitRange
{
  double Low = 0.0;
  double High = 0.0;
};

template <int DIM>
class SignedDistanceFunction
{
public:
  virtual ~SignedDistanceFunction() = default;

  // φ(x): negative inside, zero on the boundary, positive outside.
  virtual double Value(const Vec<DIM>& x) const = 0;

  // φ(x) and the part (0 … NumberOfParts() − 1) that decided it.
  virtual ImplicitSample Sample(const Vec<DIM>& x) const { return { this->Value(x), 0 }; }

  // ∇φ(x). The default takes central differences with a step relative to
  // the magnitude of x; exact functions override it.
  virtual Vec<DIM> Gradient(const Vec<DIM>& x) const
  {
    Vec<DIM> g;
    const double h = 1e-6 * (1.0 + x.cwiseAbs().maxCoeff());
    for (int i = 0; i < DIM; ++i)
    {
      Vec<DIM> a = x, b = x;
      a[i] += h;
      b[i] -= h;
      g[i] = (this->Value(a) - this->Value(b)) / (2.0 * h);
    }
    return g;
  }

  // L with |φ(x) − φ(y)| ≤ L |x − y|: 1 for exact signed distances.
  virtual double Lipschitz() const { return 1.0; }

  // A box that holds the zero set; the empty box when it is unbounded.
  virtual BoundingBox<DIM> Bounds() const { return BoundingBox<DIM>(); }

  // Parts that Sample() can report (CSG leaves); 1 for a single function.
  virtual std::int64_t NumberOfParts() const { return 1; }

  // Cheap answers for functions whose Value() searches a hierarchy (meshes,
  // and CSG trees holding them), which keep bounds cached on a grid
  // (DistanceBoundGrid.h). A CSG node asks its children for Range() to see
  // whether one child alone decides its value at x, and then only that
  // child for StepBound() (CsgFunctions.h). Both are pure functions of x and
  // the geometry, so walks stay reproducible.
  //
  // Whether Range() and StepBound() are cheaper than Value() here.
  virtual bool CachesBounds() const { return false; }

  // An interval holding φ(x). The default is exact (one Value()); cached
  // ranges may be wide, even (−∞, ∞), but must hold φ(x).
  virtual ImplicitRange Range(const Vec<DIM>& x) const
  {
    const double v = this->Value(x);
    return { v, v };
  }

  // A nearest point of the zero set to x, when the function knows one
  // exactly and cheaply (a mesh's closest point), with the part it lies on;
  // false when it does not, and callers take Newton steps instead.
  virtual bool Project(const Vec<DIM>& /*x*/, Vec<DIM>& /*point*/, std::int64_t& /*part*/) const
  {
    return false;
  }

  // A step radius r ≤ |φ(x)| / L that is at least 1 / (1 + relaxation) of
  // it, and equal to it whenever r < epsilon (so that walks stop exactly
  // where they would with |φ(x)| / L). The default is exact.
  virtual double StepBound(const Vec<DIM>& x, double /*relaxation*/, double /*epsilon*/) const
  {
    return this->DistanceBound(x);
  }

  // The conservative step radius |φ(x)| / L (never more than the distance).
  double DistanceBound(const Vec<DIM>& x) const { return std::abs(this->Value(x)) / this->Lipschitz(); }
};

// The largest |φ(a) − φ(b)| / |a − b| seen on `pairs` short random segments
// in `box` (fixed seed): a check that a Lipschitz bound is not too small,
// since a function's scale is never to be trusted. `side` restricts it to
// where walks go: −1 inside (φ < 0 at both ends), +1 outside, 0 anywhere.
template <int DIM>
double ObservedLipschitz(
  const SignedDistanceFunction<DIM>& phi, const BoundingBox<DIM>& box, int pairs, int side)
{
  if (box.IsEmpty())
  {
    return 0.0;
  }
  const Vec<DIM> extent = box.Extent();
  const double step = 1e-3 * std::max(box.Diagonal(), 1e-300);
  RandomStream rng(0x11b5c4u, 0);
  double largest = 0.0;
  for (int i = 0; i < pairs; ++i)
  {
    Vec<DIM> a;
    for (int k = 0; k < DIM; ++k)
    {
      a[k] = box.Min[k] + rng.NextDouble() * extent[k];
    }
    const Vec<DIM> b = a + step * SampleUnitSphere<DIM>(rng);
    const double fa = phi.Value(a);
    const double fb = phi.Value(b);
    const bool onSide = side == 0 || (side < 0 ? fa < 0.0 && fb < 0.0 : fa > 0.0 && fb > 0.0);
    if (onSide && std::isfinite(fa) && std::isfinite(fb))
    {
      largest = std::max(largest, std::abs(fa - fb) / step);
    }
  }
  return largest;
}
} // namespace gridfree

#endif
