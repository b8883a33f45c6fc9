// The weight a walk on stars takes when its ray from x meets the boundary of
// its star-shaped region St(x, R) at distance r (Documentation/
// WalkOnStars.md §1, Eqn. WoSt-4).
//
// Boundary term of Green's identity on St: ∫_{∂St} P(x, z) u(z) dz with
// P = −∂G/∂n_z, G the ball's Green's function (GreensFunctions.h). Along a
// ray of direction v, dz = r^{n−1} dω / (n·v), so with v uniform on the
// sphere (density 1/|S|) the term is E[Q(r) u(z)] with
//
//   Q(r) = −|S| r^{n−1} G'(r).
//
// For Δ the ball's G differs from the free-space one by a constant, so
// Q = 1 at every r. For Δ − c (s = √c, z = sR):
//   2D  Q(r) = sr·[K1(sr) + I1(sr) K0(z)/I0(z)],
//   3D  Q(r) = e^{−sr}(1 + sr) + (sr)² i1(sr) e^{−z}/sinh z,
// with Q(0) = 1 and Q(R) = C, the ball's boundary weight (1/I0(z), z/sinh z).
// Both are written in the scaled Bessel functions (BesselFunctions.h) so
// they stay finite for any z.
#ifndef GRIDFREE_STARS_STAR_KERNELS_H
#define GRIDFREE_STARS_STAR_KERNELS_H

#include <gridfree/math/BesselFunctions.h>

#include <cmath>

namespace gridfree
{
// Q(r) of the screened equation with s = √c in a ball of radius R.
template <int DIM>
double ScreenedRayWeight(double r, double R, double s)
{
  const double sr = s * r;
  const double z = s * R;
  if (!(sr > 0.0))
  {
    return 1.0;
  }
  if constexpr (DIM == 2)
  {
    const double ratio = BesselK0Scaled(z) / BesselI0Scaled(z);
    return sr * BesselK1Scaled(sr) * std::exp(-sr) +
      sr * BesselI1Scaled(sr) * ratio * std::exp(sr - 2.0 * z);
  }
  else
  {
    // e^{−z}/sinh z = 2 e^{−2z} / (1 − e^{−2z}); i1(sr) = e^{sr} i1e(sr).
    return std::exp(-sr) * (1.0 + sr) +
      sr * sr * SphericalBesselI1Scaled(sr) * 2.0 * std::exp(sr - 2.0 * z) /
      (-std::expm1(-2.0 * z));
  }
}
} // namespace gridfree

#endif
