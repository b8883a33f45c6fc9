// Tests of gridfree/cache/ScreenedBallSeries.h, deterministic: the
// screened ball's Poisson kernel reproduces solutions of Δu = k²u and
// their gradients and Hessians by quadrature over the sphere, at points up
// to the reach and for kR from 10⁻³ to 200, and solves the screened
// equation in x (the trace of its Hessian is k² times it) up to the centre;
// it becomes the Laplace kernel as k → 0;
// the regular part H equals the free-space Green's function on the sphere
// (so G_B vanishes there) and its gradient and Hessian agree with finite
// differences;
// the ball integral of G_B is continuous where it changes formula.
#include <gridfree/cache/ScreenedBallSeries.h>
#include "Quadrature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// Σ over quadrature points n on the unit sphere (circle) of weight·f(n),
// the weights summing to 1 (the mean over the sphere).
template <int DIM>
void SphereMean(const std::function<void(const Vec<DIM>&, double)>& visit)
{
  if constexpr (DIM == 3)
  {
    const GaussLegendre rule(160);
    const int azimuths = 320;
    for (std::size_t i = 0; i < rule.Nodes.size(); ++i)
    {
      const double z = rule.Nodes[i];
      const double s = std::sqrt(1.0 - z * z);
      for (int j = 0; j < azimuths; ++j)
      {
        const double phi = 2.0 * M_PI * (j + 0.5) / azimuths;
        visit(Vec<3>(s * std::cos(phi), s * std::sin(phi), z), 0.5 * rule.Weights[i] / azimuths);
      }
    }
  }
  else
  {
    const int count = 2048; // the trapezoid rule: spectral for periodic data
    for (int j = 0; j < count; ++j)
    {
      const double phi = 2.0 * M_PI * (j + 0.5) / count;
      visit(Vec<2>(std::cos(phi), std::sin(phi)), 1.0 / count);
    }
  }
}

// u = e^{k d·y} solves Δu = k²u: the kernel's mean against it is u(x), and
// the gradient's is k d u(x), for x at ρ/R up to 0.6. The data are scaled
// to at most 1 on the sphere, and the error is measured against that
// scale: for large kR, u(x) is exponentially smaller than the data, and the
// series' truncation is bounded against the data (a_l ≤ (ρ/R)^l).
template <int DIM>
void ExpectKernelReproducesExponentials(double k, double R)
{
  const ScreenedBallSeries<DIM> series(k, R, 0.6);
  Vec<DIM> d = Vec<DIM>::Zero();
  d[0] = 0.6;
  d[1] = -0.8;
  const Vec<DIM> centre = Vec<DIM>::Constant(0.25);
  const auto u = [&](const Vec<DIM>& y) { return std::exp(k * (d.dot(y - centre) - R)); };
  for (double t : { 0.0, 0.2, 0.45, 0.6 })
  {
    Vec<DIM> e = Vec<DIM>::Zero();
    e[0] = 0.48;
    e[1] = 0.6;
    e[DIM - 1] += 0.64;
    e.normalize();
    const Vec<DIM> x = centre + t * R * e;
    typename ScreenedBallSeries<DIM>::Radial radial;
    series.RadialAt(t * R, radial, true);
    double mean = 0.0;
    Vec<DIM> gradient = Vec<DIM>::Zero();
    Mat<DIM> hessian = Mat<DIM>::Zero();
    SphereMean<DIM>([&](const Vec<DIM>& n, double weight) {
      const double value = u(centre + R * n);
      Vec<DIM> dw;
      Mat<DIM> d2w;
      const double w = series.Kernel(radial, e, n, &dw, &d2w);
      mean += weight * w * value;
      gradient += (weight * value) * dw;
      hessian += (weight * value) * d2w;
      // The kernel solves the screened equation in x: Δₓw = k² w.
      EXPECT_NEAR(d2w.trace(), k * k * w, 1e-9 * (k * k + 1.0 / (R * R)) * (1.0 + std::abs(w)))
        << "k " << k << " R " << R << " t " << t;
    });
    EXPECT_NEAR(mean, u(x), 1e-12) << "k " << k << " R " << R << " t " << t;
    for (int a = 0; a < DIM; ++a)
    {
      EXPECT_NEAR(gradient[a], k * d[a] * u(x), 1e-11 * (k + 1.0 / R)) << "k " << k << " t " << t;
      for (int b = 0; b < DIM; ++b)
      {
        EXPECT_NEAR(hessian(a, b), k * k * d[a] * d[b] * u(x), 1e-10 * PowerOf<2>(k + 1.0 / R))
          << "k " << k << " t " << t << " entry " << a << b;
      }
    }
  }
}

template <int DIM>
void ExpectLaplaceLimit()
{
  const double R = 1.5;
  const ScreenedBallSeries<DIM> series(1e-7, R, 0.6);
  typename ScreenedBallSeries<DIM>::Radial radial;
  Vec<DIM> e = Vec<DIM>::Zero();
  e[0] = 1.0;
  const double rho = 0.55 * R;
  series.RadialAt(rho, radial);
  for (int j = 0; j < 16; ++j)
  {
    const double angle = 0.2 + 0.37 * j;
    Vec<DIM> n = Vec<DIM>::Zero();
    n[0] = std::cos(angle);
    n[1] = std::sin(angle);
    const double d2 = (rho * e - R * n).squaredNorm();
    const double exact = DIM == 3 ? R * (R * R - rho * rho) / (d2 * std::sqrt(d2))
                                  : (R * R - rho * rho) / d2;
    EXPECT_NEAR(series.Kernel(radial, e, n, nullptr), exact, 1e-9 * exact) << j;
  }
  EXPECT_NEAR(series.BallIntegral(rho, radial), (R * R - rho * rho) / (2.0 * DIM), 1e-12);
}

// H(x, y) = G(|x − y|) for y on the sphere; ∇ₓH by central differences.
template <int DIM>
void ExpectRegularPartMatchesOnTheSphere(double k, double R)
{
  const ScreenedBallSeries<DIM> series(k, R, 0.6);
  typename ScreenedBallSeries<DIM>::Radial atX, atY, shifted;
  for (double t : { 0.0, 0.3, 0.6 })
  {
    Vec<DIM> e = Vec<DIM>::Zero();
    e[0] = 0.8;
    e[1] = 0.6;
    const Vec<DIM> x = t * R * e;
    series.RadialAt(t * R, atX, true);
    for (int j = 0; j < 12; ++j)
    {
      const double angle = 0.1 + 0.53 * j;
      Vec<DIM> n = Vec<DIM>::Zero();
      n[0] = std::cos(angle);
      n[DIM - 1] = std::sin(angle);
      for (double s : { 1.0, 0.7 })
      {
        series.RadialAt(s * R, atY);
        Vec<DIM> gradient;
        Mat<DIM> hessian;
        const double h = series.Regular(atX, atY, e, n, &gradient, &hessian);
        if (s == 1.0)
        {
          double slope;
          const double g = series.FreeSpace((x - R * n).norm(), &slope);
          EXPECT_NEAR(h, g, 1e-11 * std::abs(g) + 1e-13) << "k " << k << " t " << t << " j " << j;
        }
        // Central differences of H along each axis (x moves, y stays).
        const double step = 1e-5 * R;
        for (int a = 0; a < DIM; ++a)
        {
          double side[2];
          Vec<DIM> ahead, behind;
          for (int sign = 0; sign < 2; ++sign)
          {
            Vec<DIM> xs = x;
            xs[a] += sign == 0 ? step : -step;
            const double rho = xs.norm();
            const Vec<DIM> es = rho > 0.0 ? Vec<DIM>(xs / rho) : e;
            series.RadialAt(rho, shifted);
            side[sign] = series.Regular(shifted, atY, es, n, sign == 0 ? &ahead : &behind);
          }
          const double difference = (side[0] - side[1]) / (2.0 * step);
          EXPECT_NEAR(gradient[a], difference, 1e-6 * (std::abs(difference) + 1.0 / R))
            << "k " << k << " t " << t << " axis " << a;
          // The Hessian's column a: central differences of the gradient.
          for (int b = 0; b < DIM; ++b)
          {
            const double second = (ahead[b] - behind[b]) / (2.0 * step);
            EXPECT_NEAR(hessian(b, a), second, 1e-5 * (std::abs(second) + 1.0 / (R * R)))
              << "k " << k << " t " << t << " entry " << b << a;
          }
        }
      }
    }
  }
}
} // namespace

TEST(ScreenedBallSeries, KernelReproducesScreenedSolutions)
{
  for (double k : { 1e-3, 0.5, 2.0, 20.0, 200.0 })
  {
    ExpectKernelReproducesExponentials<3>(k, 1.0);
    ExpectKernelReproducesExponentials<2>(k, 1.0);
  }
  ExpectKernelReproducesExponentials<3>(3.0, 0.05);
  ExpectKernelReproducesExponentials<2>(3.0, 7.0);
}

TEST(ScreenedBallSeries, LaplaceLimit)
{
  ExpectLaplaceLimit<3>();
  ExpectLaplaceLimit<2>();
}

TEST(ScreenedBallSeries, GreensFunctionVanishesOnTheSphere)
{
  for (double k : { 0.01, 1.0, 2.0, 30.0 })
  {
    ExpectRegularPartMatchesOnTheSphere<3>(k, 1.0);
    ExpectRegularPartMatchesOnTheSphere<2>(k, 1.0);
  }
}

TEST(ScreenedBallSeries, BallIntegralIsContinuousWhereItsFormulaChanges)
{
  for (double rho : { 0.0, 0.3, 0.6 })
  {
    const ScreenedBallSeries<3> below(1.0 - 1e-9, 1.0, 0.6), above(1.0 + 1e-9, 1.0, 0.6);
    ScreenedBallSeries<3>::Radial a, b;
    below.RadialAt(rho, a);
    above.RadialAt(rho, b);
    EXPECT_NEAR(below.BallIntegral(rho, a), above.BallIntegral(rho, b), 1e-9);
    const ScreenedBallSeries<2> below2(1.0 - 1e-9, 1.0, 0.6), above2(1.0 + 1e-9, 1.0, 0.6);
    ScreenedBallSeries<2>::Radial a2, b2;
    below2.RadialAt(rho, a2);
    above2.RadialAt(rho, b2);
    EXPECT_NEAR(below2.BallIntegral(rho, a2), above2.BallIntegral(rho, b2), 1e-9);
  }
}
