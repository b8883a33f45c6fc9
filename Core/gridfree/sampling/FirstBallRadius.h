// Radii for the first ball's derivative integrals ∫ h ∇G and ∫ h G over
// B(x, R), where the kernels' pole and, for strong screening, their decay
// make one density a poor fit for every r. The radius is drawn from a
// mixture of
//   q_h ∝ 1 − (r/R)^n   (∝ r^{n−1}|∇G_harmonic|: cancels the pole),
//   q_v ∝ r^{n−1}       (covers the rim),
//   q_e ∝ e^{−sr}       (follows Yukawa kernels that decay within the ball,
//                        only when z = sR > 1),
// and a sample's weight |S| r^{n−1}/q(r) with the exact mixture density q
// keeps any radial kernel unbiased: ∫_B k(|d|) h dy ≈ weight · k(r) · h(x + rω).
#ifndef GRIDFREE_SAMPLING_FIRST_BALL_RADIUS_H
#define GRIDFREE_SAMPLING_FIRST_BALL_RADIUS_H

#include <gridfree/math/Vector.h>
#include <gridfree/sampling/BallSampling.h>
#include <gridfree/sampling/Random.h>

#include <algorithm>
#include <cmath>

namespace gridfree
{
template <int DIM>
struct FirstBallRadius
{
  // The exponential component only helps when the kernels decay within the
  // ball (z > 1).
  static int MixtureSize(double z) { return z > 1.0 ? 3 : 2; }

  // A radius in (0, R] from the mixture; z = sqrt(c)·R (0 for c = 0).
  static double Sample(double radius, double z, RandomStream& rng)
  {
    const int parts = MixtureSize(z);
    const double pick = rng.NextDouble() * parts;
    if (pick < 1.0)
    {
      for (;;)
      {
        const double t = rng.NextDouble();
        if (rng.NextDouble() < 1.0 - PowerOf<DIM>(t))
        {
          return std::max(t, 1e-300) * radius;
        }
      }
    }
    if (pick < 2.0)
    {
      return radius * std::pow(std::max(rng.NextDouble(), 1e-300), 1.0 / DIM);
    }
    const double s = z / radius;
    const double r = -std::log1p(rng.NextDouble() * std::expm1(-z)) / s;
    return std::min(std::max(r, 1e-300 * radius), radius);
  }

  // The mixture's density at r.
  static double Density(double r, double radius, double z)
  {
    const double n = DIM;
    const double t = r / radius;
    const double tn = PowerOf<DIM>(t);
    const int parts = MixtureSize(z);
    double q = (n + 1.0) / (n * radius) * (1.0 - tn) + n * PowerOf<DIM - 1>(t) / radius;
    if (parts == 3)
    {
      const double s = z / radius;
      q += s * std::exp(-s * r) / -std::expm1(-z);
    }
    return q / parts;
  }

  // |S| r^{n−1}/q(r): the volume weight of a sample at radius r with a
  // uniform direction.
  static double Weight(double r, double radius, double z)
  {
    return UnitSphereArea<DIM>() * PowerOf<DIM - 1>(r) / Density(r, radius, z);
  }
};
} // namespace gridfree

#endif
