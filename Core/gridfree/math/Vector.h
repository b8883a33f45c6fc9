// Fixed-size vector aliases shared by the estimator core.
//
// The core is templated on the spatial dimension DIM (2 or 3) and uses Eigen's
// fixed-size types so that 2D and 3D code paths compile to straight-line code.
#ifndef GRIDFREE_MATH_VECTOR_H
#define GRIDFREE_MATH_VECTOR_H

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gridfree
{
template <int DIM>
using Vec = Eigen::Matrix<double, DIM, 1>;

template <int DIM>
using VecF = Eigen::Matrix<float, DIM, 1>;

template <int DIM>
using Mat = Eigen::Matrix<double, DIM, DIM>;

using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

// x^N for a small non-negative integer N, by multiplication: std::pow with
// an integer exponent calls libm's pow, which took 5% of a CT solve's time
// (the ball's R^DIM at every step).
template <int N>
constexpr double PowerOf(double x)
{
  static_assert(N >= 0 && N <= 4, "small powers only");
  if constexpr (N == 0)
  {
    return 1.0;
  }
  else
  {
    return x * PowerOf<N - 1>(x);
  }
}
} // namespace gridfree

#endif
