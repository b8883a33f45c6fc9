// Where a walk far outside the boundary comes back, if it ever does
// (exterior problems, paper Sec. 2.6).
//
// Let every boundary (and every source) lie inside the sphere S = ∂B(c, ρ).
// Brownian motion started at x with r = |x − c| > ρ
// - in 3D hits S with probability ρ/r (the harmonic function ρ/r that is 1 on
//   S and 0 at infinity) and otherwise leaves for ever;
// - in 2D hits S with probability 1 (Brownian motion in the plane is
//   recurrent).
// Given that it hits S, the hitting point is distributed by the exterior
// Poisson kernel (r² − ρ²)/(|S| ρ |x − y|^n) normalised to one, which is the
// interior Poisson kernel of the Kelvin image x* = c + ρ²(x − c)/r² (the two
// kernels differ only by the factor r/ρ in 3D).
//
// So a walk far away can be ended or returned to S in one step, exactly:
// Russian roulette whose survival probability is the true return probability,
// so that survivors keep weight 1 and the estimator stays unbiased. Sampling
// the Poisson kernel in closed form:
// - 2D: the kernel in the polar angle is a wrapped Cauchy distribution with
//   concentration k = |x* − c|/ρ = ρ/r;
// - 3D: with a = |x* − c| and t the cosine of the angle to x − c, the CDF
//   F(t) = (ρ² − a²)/(2a) · [ (ρ² + a² − 2aρt)^(−1/2) − 1/(ρ + a) ]
//   inverts to the expression in SampleExteriorReturn3 (written without the
//   cancellation of the direct inverse when a ≪ ρ).
#ifndef GRIDFREE_ESTIMATORS_EXTERIOR_RETURN_H
#define GRIDFREE_ESTIMATORS_EXTERIOR_RETURN_H

#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>

namespace gridfree
{
// Probability that Brownian motion at distance r > rho from c ever reaches
// the sphere of radius rho around c.
template <int DIM>
inline double ReturnProbability(double r, double rho)
{
  return DIM == 2 ? 1.0 : std::min(1.0, rho / r);
}

// Point where Brownian motion from x (|x − c| > rho) first hits the sphere
// ∂B(c, rho), given that it does.
template <int DIM>
Vec<DIM> SampleExteriorReturn(
  const Vec<DIM>& x, const Vec<DIM>& c, double rho, RandomStream& rng);

template <>
inline Vec<2> SampleExteriorReturn<2>(
  const Vec<2>& x, const Vec<2>& c, double rho, RandomStream& rng)
{
  const Vec<2> d = x - c;
  const double r = d.norm();
  const double k = rho / r; // concentration of the wrapped Cauchy law
  const double u = rng.NextDouble();
  // Inverse CDF of the wrapped Cauchy distribution on (−π, π).
  const double theta = 2.0 * std::atan((1.0 - k) / (1.0 + k) * std::tan(M_PI * (u - 0.5)));
  const double base = std::atan2(d[1], d[0]) + theta;
  return c + rho * Vec<2>(std::cos(base), std::sin(base));
}

template <>
inline Vec<3> SampleExteriorReturn<3>(
  const Vec<3>& x, const Vec<3>& c, double rho, RandomStream& rng)
{
  const Vec<3> d = x - c;
  const double r = d.norm();
  const Vec<3> axis = d / r;
  const double a = rho * rho / r; // distance of the Kelvin image from c
  const double e = 2.0 * rng.NextDouble() - 1.0;
  const double denominator = rho + a * e; // ρ − a + 2aU
  double t = (rho * rho * e + 0.5 * a * rho * (e * e + 3.0) + a * a * e +
               a * a * a * (e * e - 1.0) / (2.0 * rho)) /
    (denominator * denominator);
  t = std::max(-1.0, std::min(1.0, t));
  // An orthonormal frame around the axis.
  const Vec<3> helper = std::abs(axis[0]) < 0.9 ? Vec<3>(1, 0, 0) : Vec<3>(0, 1, 0);
  const Vec<3> e1 = axis.cross(helper).normalized();
  const Vec<3> e2 = axis.cross(e1);
  const double phi = 2.0 * M_PI * rng.NextDouble();
  const double s = std::sqrt(std::max(0.0, 1.0 - t * t));
  return c + rho * (t * axis + s * (std::cos(phi) * e1 + std::sin(phi) * e2));
}
} // namespace gridfree

#endif
