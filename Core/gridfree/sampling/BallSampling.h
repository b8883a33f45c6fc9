// Uniform samples in the unit ball B^DIM and the measures of the unit ball and
// unit sphere, used by source-term estimators (paper Eqn. 8: y ~ U(B(x))).
#ifndef GRIDFREE_SAMPLING_BALL_SAMPLING_H
#define GRIDFREE_SAMPLING_BALL_SAMPLING_H

#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <cmath>

namespace gridfree
{
// |B| of the unit ball: π (2D), 4π/3 (3D); a radius-R ball has R^DIM times this.
template <int DIM>
constexpr double UnitBallVolume()
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");
  return DIM == 2 ? M_PI : 4.0 * M_PI / 3.0;
}

// |S| of the unit sphere: 2π (2D), 4π (3D); a radius-R sphere has R^{DIM−1} times this.
template <int DIM>
constexpr double UnitSphereArea()
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");
  return DIM == 2 ? 2.0 * M_PI : 4.0 * M_PI;
}

// Uniform point in the unit ball: the volume inside radius ρ is ρ^DIM, so
// ρ = U^{1/DIM} with a uniform direction.
template <int DIM>
Vec<DIM> SampleUnitBall(RandomStream& rng)
{
  const Vec<DIM> direction = SampleUnitSphere<DIM>(rng);
  const double u = rng.NextDouble();
  const double rho = DIM == 2 ? std::sqrt(u) : std::cbrt(u);
  return rho * direction;
}
} // namespace gridfree

#endif
