// Uniform samples on the unit sphere S^{DIM-1}, the step distribution of walk
// on spheres (paper Sec. 2.2.1: x_{k+1} uniform on the largest sphere).
#ifndef GRIDFREE_SAMPLING_SPHERE_SAMPLING_H
#define GRIDFREE_SAMPLING_SPHERE_SAMPLING_H

#include <gridfree/sampling/Random.h>
#include <gridfree/math/Vector.h>

#include <cmath>

namespace gridfree
{
template <int DIM>
Vec<DIM> SampleUnitSphere(RandomStream& rng);

// Circle: uniform angle.
template <>
inline Vec<2> SampleUnitSphere<2>(RandomStream& rng)
{
  const double phi = 2.0 * M_PI * rng.NextDouble();
  return Vec<2>(std::cos(phi), std::sin(phi));
}

// 2-sphere: Archimedes' hat-box theorem, z uniform in [-1, 1].
template <>
inline Vec<3> SampleUnitSphere<3>(RandomStream& rng)
{
  const double z = 1.0 - 2.0 * rng.NextDouble();
  const double phi = 2.0 * M_PI * rng.NextDouble();
  const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vec<3>(rho * std::cos(phi), rho * std::sin(phi), z);
}
} // namespace gridfree

#endif
