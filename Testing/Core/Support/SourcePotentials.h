// Free-space potentials of point and straight curve sources for Δu = f
// (fundamental solutions Φ with ΔΦ = δ: −1/(4π r) in 3D, ln(r)/(2π) in
// 2D), with gradients and Hessians by Gauss–Legendre quadrature on many
// panels along the curve (points away from it): the exact solutions of the
// point- and curve-source tests.
#ifndef GRIDFREE_TESTING_SOURCE_POTENTIALS_H
#define GRIDFREE_TESTING_SOURCE_POTENTIALS_H

#include <gridfree/math/Vector.h>
#include <gridfree/sampling/BallSampling.h>

#include <algorithm>
#include <cmath>

namespace gridfree
{
namespace testing
{
template <int DIM>
double Fundamental(double r)
{
  return DIM == 3 ? -1.0 / (4.0 * M_PI * r) : std::log(r) / (2.0 * M_PI);
}

// ∇Φ(d) = d/(|S| rⁿ), d = x − z.
template <int DIM>
Vec<DIM> FundamentalGradient(const Vec<DIM>& d)
{
  return d / (UnitSphereArea<DIM>() * std::pow(d.norm(), DIM));
}

// Four-point Gauss–Legendre nodes and weights on [−1, 1], per panel.
constexpr double kPanelNodes[4] = { -0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
  0.8611363115940526 };
constexpr double kPanelWeights[4] = { 0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
  0.3478548451374538 };

// u of a straight curve source from a to b with strength linear from sa to
// sb, by Gauss–Legendre quadrature on many panels (x is away from the curve).
template <int DIM>
double CurvePotential(const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& b, double sa, double sb)
{
  const int panels = 400;
  const double length = (b - a).norm();
  double sum = 0.0;
  for (int p = 0; p < panels; ++p)
  {
    for (int q = 0; q < 4; ++q)
    {
      const double t = (p + 0.5 * (kPanelNodes[q] + 1.0)) / panels;
      const Vec<DIM> y = a + t * (b - a);
      sum += kPanelWeights[q] * 0.5 / panels * (sa + t * (sb - sa)) * Fundamental<DIM>((x - y).norm());
    }
  }
  return sum * length;
}

// Gradient and Hessian of the same curve potential, by the same quadrature
// of ∇Φ(d) = d/(|S| rⁿ) and ∇²Φ(d) = (I − n d̂ d̂ᵀ)/(|S| rⁿ), d = x − y.
template <int DIM>
void CurvePotentialDerivatives(const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& b,
  double sa, double sb, Vec<DIM>& gradient, Mat<DIM>& hessian)
{
  const int panels = 400;
  const double length = (b - a).norm();
  gradient.setZero();
  hessian.setZero();
  for (int p = 0; p < panels; ++p)
  {
    for (int q = 0; q < 4; ++q)
    {
      const double t = (p + 0.5 * (kPanelNodes[q] + 1.0)) / panels;
      const Vec<DIM> d = x - (a + t * (b - a));
      const double r = d.norm();
      const double w = kPanelWeights[q] * 0.5 / panels * (sa + t * (sb - sa)) * length /
        (UnitSphereArea<DIM>() * std::pow(r, DIM));
      gradient += w * d;
      hessian += w * (Mat<DIM>::Identity() - DIM * d * d.transpose() / (r * r));
    }
  }
}

template <int DIM>
double DistanceToSegment(const Vec<DIM>& x, const Vec<DIM>& a, const Vec<DIM>& b)
{
  const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (x - (a + t * (b - a))).norm();
}
} // namespace testing
} // namespace gridfree

#endif
