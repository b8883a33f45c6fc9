// Spatially varying coefficients of the second-order equation
//
//   ∇·(α ∇u) − σ u = f       (α > 0, σ ≥ 0; the house's sign: Δu = f for α = 1)
//
// and the change of variables that turns it into a screened Poisson
// equation with a varying coefficient (Sawhney, Seyb, Jarosz and Crane,
// "Grid-Free Monte Carlo for PDEs with Spatially Varying Coefficients",
// SIGGRAPH 2022, Sec. 4). With U = √α u,
//
//   ∇·(α∇u) = √α ΔU − U Δ√α,
//
// so the equation becomes
//
//   ΔU − σ′ U = f′,    σ′ = σ/α + Δα/(2α) − |∇α|²/(4α²),    f′ = f/√α,
//
// with U = √α g on the boundary (Δ√α/√α = Δα/(2α) − |∇α|²/(4α²) follows
// from √α = e^{(ln α)/2}). σ′ can be negative where α is concave; the walk
// (VaryingCoefficientWalk.h) stays unbiased for any sign. α must be twice
// differentiable: a field gives α with its gradient and Laplacian.
//
// The Pennes bioheat equation ∇·(k∇T) − w(T − T_a) + Q = 0 is this equation
// for u = T − T_a with α = k, σ = w and f = −Q.
#ifndef GRIDFREE_COEFFICIENTS_VARYING_COEFFICIENTS_H
#define GRIDFREE_COEFFICIENTS_VARYING_COEFFICIENTS_H

#include <gridfree/math/Vector.h>

#include <cmath>
#include <sstream>
#include <string>

namespace gridfree
{
// The coefficients at one point.
template <int DIM>
struct CoefficientSample
{
  double Alpha = 1.0;                                // α > 0
  Vec<DIM> AlphaGradient = Vec<DIM>::Zero();         // ∇α
  double AlphaLaplacian = 0.0;                       // Δα
  double Absorption = 0.0;                           // σ ≥ 0
  double Source = 0.0;                               // f
};

// α, σ and f as functions of the point. Evaluate is called by every
// thread at once: implementations keep no scratch state (or keep it per
// thread).
template <int DIM>
class CoefficientField
{
public:
  virtual ~CoefficientField() = default;
  virtual void Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const = 0;
  // False when f ≡ 0: walks then skip the source's samples.
  virtual bool HasSource() const { return true; }
};

// What the walk of U = √α u needs at a point.
struct TransformedCoefficients
{
  double SqrtAlpha = 1.0;
  double Screening = 0.0; // σ′
  double Source = 0.0;    // f′ = f/√α
};

// α > 0, σ ≥ 0 and everything finite: what the equation needs.
template <int DIM>
bool CoefficientsUsable(const CoefficientSample<DIM>& c)
{
  return c.Alpha > 0.0 && std::isfinite(c.Alpha) && c.AlphaGradient.allFinite() &&
    std::isfinite(c.AlphaLaplacian) && c.Absorption >= 0.0 && std::isfinite(c.Absorption) &&
    std::isfinite(c.Source);
}

// Which coefficient is unusable at x, and why, for an error message.
template <int DIM>
std::string DescribeUnusable(const CoefficientSample<DIM>& c, const Vec<DIM>& x)
{
  std::ostringstream where;
  where << " at (";
  for (int i = 0; i < DIM; ++i)
  {
    where << (i ? ", " : "") << x[i];
  }
  where << ")";
  if (!(c.Alpha > 0.0) || !std::isfinite(c.Alpha))
  {
    return "the diffusion coefficient alpha must be positive and finite; it is " +
      std::to_string(c.Alpha) + where.str();
  }
  if (!c.AlphaGradient.allFinite() || !std::isfinite(c.AlphaLaplacian))
  {
    return "the derivatives of alpha are not finite" + where.str();
  }
  if (!(c.Absorption >= 0.0) || !std::isfinite(c.Absorption))
  {
    return "the absorption coefficient sigma must be finite and >= 0; it is " +
      std::to_string(c.Absorption) + where.str();
  }
  return "the source f is not finite" + where.str();
}

template <int DIM>
TransformedCoefficients Transform(const CoefficientSample<DIM>& c)
{
  TransformedCoefficients t;
  t.SqrtAlpha = std::sqrt(c.Alpha);
  const double invAlpha = 1.0 / c.Alpha;
  t.Screening = c.Absorption * invAlpha + 0.5 * c.AlphaLaplacian * invAlpha -
    0.25 * c.AlphaGradient.squaredNorm() * invAlpha * invAlpha;
  t.Source = c.Source / t.SqrtAlpha;
  return t;
}
} // namespace gridfree

#endif
