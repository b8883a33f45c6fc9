// Closed-form test solutions with exact gradients and Hessians, shared by
// the deterministic kernel tests and the statistical estimator tests.
#ifndef GRIDFREE_TESTING_TESTSOLUTIONS_H
#define GRIDFREE_TESTING_TESTSOLUTIONS_H

#include <gridfree/math/Vector.h>

#include <cmath>
#include <functional>

namespace gridfree
{
namespace testing
{
template <int DIM>
struct Solution
{
  std::function<double(const Vec<DIM>&)> U;
  std::function<Vec<DIM>(const Vec<DIM>&)> Gradient;
  std::function<Mat<DIM>(const Vec<DIM>&)> Hessian;
};

template <int DIM>
double Laplacian(const Solution<DIM>& s, const Vec<DIM>& y)
{
  return s.Hessian(y).trace();
}

// u = e^{a·y} sin(b·y) + y0² y1 + 1: rich in every degree and not harmonic,
// so Poisson and screened problems need a source f = Δu − c u.
template <int DIM>
Solution<DIM> SmoothSolution()
{
  Vec<DIM> a, b;
  if constexpr (DIM == 2)
  {
    a << 0.7, -0.4;
    b << 1.1, 0.9;
  }
  else
  {
    a << 0.7, -0.4, 0.3;
    b << 1.1, 0.9, -0.6;
  }
  Solution<DIM> s;
  s.U = [a, b](const Vec<DIM>& y) {
    return std::exp(a.dot(y)) * std::sin(b.dot(y)) + y[0] * y[0] * y[1] + 1.0;
  };
  s.Gradient = [a, b](const Vec<DIM>& y) {
    const double e = std::exp(a.dot(y)), sn = std::sin(b.dot(y)), cs = std::cos(b.dot(y));
    Vec<DIM> g = e * (sn * a + cs * b);
    g[0] += 2.0 * y[0] * y[1];
    g[1] += y[0] * y[0];
    return g;
  };
  s.Hessian = [a, b](const Vec<DIM>& y) {
    const double e = std::exp(a.dot(y)), sn = std::sin(b.dot(y)), cs = std::cos(b.dot(y));
    Mat<DIM> h = e *
      (sn * (a * a.transpose() - b * b.transpose()) + cs * (a * b.transpose() + b * a.transpose()));
    h(0, 0) += 2.0 * y[1];
    h(0, 1) += 2.0 * y[0];
    h(1, 0) += 2.0 * y[0];
    return h;
  };
  return s;
}
} // namespace testing
} // namespace gridfree

#endif
