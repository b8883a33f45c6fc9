// Exponentially scaled modified Bessel functions for x >= 0.
//
// The screened Poisson (Yukawa) Green's functions of a ball (paper App. B.2,
// FORMULAS.md §3) need I0, I1, K0, K1 and the spherical i1 at arguments up to
// z = R·sqrt(c), which is easily several hundred: I overflows and K underflows
// there, and their ratios become inf/inf or 0/0. The scaled forms
//
//   e^{-x} I_ν(x),  e^{x} K_ν(x),  e^{-z} i1(z)
//
// vary only algebraically, so callers can combine the exponentials by hand.
//
// Below AsymptoticThreshold the values come from Boost.Math times exp(∓x);
// above it, from the Hankel large-argument expansions, whose terms decrease
// until k ≈ 2x, so at x > 500 they reach machine precision within a few terms
// (the exponentially small e^{-2x} part of I_ν is far below rounding).
#ifndef GRIDFREE_MATH_BESSEL_FUNCTIONS_H
#define GRIDFREE_MATH_BESSEL_FUNCTIONS_H

#include <boost/math/special_functions/bessel.hpp>

#include <cmath>
#include <limits>

namespace gridfree
{
namespace bessel_detail
{
// Boost's double routines are accurate to a few ulp on their own; promoting
// to long double only costs time in the per-step evaluations.
using Policy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;

// I(500) ≈ 1e215 and K(500) ≈ 1e-219 are still comfortably representable.
constexpr double AsymptoticThreshold = 500.0;

// Σ_k sign^k a_k(ν) / x^k with a_k(ν) = Π_{j=1..k} (4ν² − (2j−1)²) / (k! 8^k):
// sign = −1 gives sqrt(2πx) e^{-x} I_ν(x), sign = +1 gives sqrt(2x/π) e^{x} K_ν(x)
// (Abramowitz & Stegun 9.7.1, 9.7.2).
inline double HankelSeries(double nu, double x, double sign)
{
  const double mu = 4.0 * nu * nu;
  double term = 1.0;
  double sum = 1.0;
  for (int k = 1; k < 60; ++k)
  {
    const double odd = 2.0 * k - 1.0;
    term *= sign * (mu - odd * odd) / (8.0 * k * x);
    sum += term;
    if (std::abs(term) < 1e-17 * std::abs(sum))
    {
      break;
    }
  }
  return sum;
}

inline double ScaledI(int nu, double x)
{
  if (x >= AsymptoticThreshold)
  {
    return HankelSeries(nu, x, -1.0) / std::sqrt(2.0 * M_PI * x);
  }
  return boost::math::cyl_bessel_i(nu, x, Policy()) * std::exp(-x);
}

inline double ScaledK(int nu, double x)
{
  if (x <= 0.0)
  {
    return std::numeric_limits<double>::infinity();
  }
  if (x >= AsymptoticThreshold)
  {
    return HankelSeries(nu, x, 1.0) * std::sqrt(M_PI / (2.0 * x));
  }
  return boost::math::cyl_bessel_k(nu, x, Policy()) * std::exp(x);
}
} // namespace bessel_detail

// e^{-x} I0(x); 1 at x = 0, ~ 1/sqrt(2πx) for large x.
inline double BesselI0Scaled(double x)
{
  return bessel_detail::ScaledI(0, x);
}

// e^{-x} I1(x); 0 at x = 0, ~ 1/sqrt(2πx) for large x.
inline double BesselI1Scaled(double x)
{
  return bessel_detail::ScaledI(1, x);
}

// e^{x} K0(x) for x > 0 (+inf at x = 0, the logarithmic pole).
inline double BesselK0Scaled(double x)
{
  return bessel_detail::ScaledK(0, x);
}

// e^{x} K1(x) for x > 0 (+inf at x = 0, the 1/x pole).
inline double BesselK1Scaled(double x)
{
  return bessel_detail::ScaledK(1, x);
}

// e^{-z} i1(z) with the modified spherical Bessel function
// i1(z) = (z cosh z − sinh z)/z² = sqrt(π/(2z)) I_{3/2}(z) (FORMULAS.md §3, "i1s").
inline double SphericalBesselI1Scaled(double z)
{
  if (z < 1.0)
  {
    // z cosh z − sinh z = z³/3 + ... cancels catastrophically for small z, so
    // sum i1(z) = Σ_k z^{2k+1} / (2^k k! (2k+3)!!) = z/3 + z³/30 + z⁵/840 + ...
    double term = z / 3.0;
    double sum = term;
    const double z2 = z * z;
    for (int k = 0; k < 30; ++k)
    {
      term *= z2 / ((2.0 * k + 2.0) * (2.0 * k + 5.0));
      sum += term;
      if (term < 1e-17 * sum)
      {
        break;
      }
    }
    return sum * std::exp(-z);
  }
  // e^{-z}(z cosh z − sinh z) = ((z − 1) + (z + 1) e^{-2z}) / 2: no overflow,
  // and for z >= 1 both parts are non-negative, so no cancellation either.
  return ((z - 1.0) + (z + 1.0) * std::exp(-2.0 * z)) / (2.0 * z * z);
}
// e^{-x} I_ℓ(x) / x^ℓ (2D, cylindrical I_ℓ) or e^{-x} i_ℓ(x) / x^ℓ (3D,
// modified spherical i_ℓ), ℓ = 0, 1, 2: finite and nonzero at x = 0, where
// they equal 1/(2^ℓ ℓ!) (2D) and 1/(2ℓ+1)!! (3D). The Hessian kernels of a
// ball (GreensFunctionHessians.h) use them as I_ℓ(sr)/I_ℓ(z) =
// e^{−(z − sr)} (r/R)^ℓ · B(sr)/B(z), which neither overflows for large z nor
// cancels for small sr.
template <int DIM>
double ScaledBesselOverPower(int ell, double x)
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");
  const double seriesLimit = DIM == 2 ? 2.0 : 3.0;
  if (x < seriesLimit)
  {
    // 2D: I_ℓ(x)/x^ℓ = Σ_k (x²/4)^k / (2^ℓ k! (k+ℓ)!);
    // 3D: i_ℓ(x)/x^ℓ = Σ_k (x²/2)^k / (k! (2ℓ+2k+1)!!). Positive terms only.
    double term = 1.0;
    if (DIM == 2)
    {
      for (int j = 1; j <= ell; ++j)
      {
        term /= 2.0 * j;
      }
    }
    else
    {
      for (int j = 1; j <= ell; ++j)
      {
        term /= 2.0 * j + 1.0;
      }
    }
    double sum = term;
    const double q = DIM == 2 ? 0.25 * x * x : 0.5 * x * x;
    for (int k = 1; k < 60; ++k)
    {
      term *= DIM == 2 ? q / (k * double(k + ell)) : q / (k * (2.0 * ell + 2.0 * k + 1.0));
      sum += term;
      if (term < 1e-17 * sum)
      {
        break;
      }
    }
    return sum * std::exp(-x);
  }
  if (DIM == 2)
  {
    return bessel_detail::ScaledI(ell, x) / std::pow(x, ell);
  }
  // 3D closed forms, scaled by e^{-x}; for x >= 3 the recurrence
  // i2 = i0 − 3 i1/x loses less than one digit.
  const double i0 = -std::expm1(-2.0 * x) / (2.0 * x);
  if (ell == 0)
  {
    return i0;
  }
  const double i1 = SphericalBesselI1Scaled(x);
  if (ell == 1)
  {
    return i1 / x;
  }
  return (i0 - 3.0 * i1 / x) / (x * x);
}

// e^{x} K_ν(x) for integer ν >= 0 and x > 0.
inline double BesselKScaled(int nu, double x)
{
  return bessel_detail::ScaledK(nu, x);
}
} // namespace gridfree

#endif
