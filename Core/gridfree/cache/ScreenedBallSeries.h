// The kernels of a ball B(c, R) for the screened equation Δu − k²u = f
// (k² the screening coefficient; FORMULAS.md §3, paper App. B.2), at any
// point x of the ball's inner part, |x − c| = ρ ≤ Reach·R: the sphere
// cache's answers off the centre (SphereCache.h). Walk on spheres needs
// them at the centre only, where they are closed forms; off the centre they
// are series over the angle γ between x − c and a point's direction from c
// (Legendre polynomials P_l in 3D, cos(lγ) = T_l in 2D):
//
//   Poisson kernel  |∂B| P(x, s) = Σ_l β_l a_l(ρ) Φ_l(cos γ),
//   a_l(ρ) = i_l(kρ)/i_l(kR) (3D), I_l(kρ)/I_l(kR) (2D),
//   β_l = 2l + 1 (3D), 1 then 2 (2D),
//
//   Green's function G_B(x, y) = G(|x − y|) − H(x, y), zero for y on ∂B,
//   G(r) = e^{−kr}/(4πr) (3D), K0(kr)/(2π) (2D), and
//   H(x, y) = κ Σ_l β_l c_l a_l(|x − c|) a_l(|y − c|) Φ_l(cos γ),
//   c_l = i_l(kR) k_l(kR), κ = k/(4π) (3D; k_0(z) = e^{−z}/z);
//   c_l = I_l(kR) K_l(kR), κ = 1/(2π) (2D)
//
// from the addition theorems e^{−k|x−y|}/|x−y| = k Σ (2l+1) i_l(kr<)
// k_l(kr>) P_l and K0(k|x−y|) = Σ β_l I_l(kr<) K_l(kr>) cos(lγ). With k → 0
// they become the Laplace kernels SphereCache.h uses (a_l → (ρ/R)^l).
//
// Nothing overflows for large kR: only ratios are formed. r_l(z) =
// i_l(z)/i_{l−1}(z) (I_l/I_{l−1}) comes from the backward recurrence
// r_l = z/(α_l + z r_{l+1}), α_l = 2l + DIM − 2 (stable for the minimal
// solution, started well past l and z), a_l = a_{l−1} r_l(kρ)/r_l(kR),
// and c_l from the Wronskian, c_l = 1/(z^{DIM−1} (r_{l+1}(z) + s_l(z)))
// with s_l = k_{l+1}/k_l (K_{l+1}/K_l) by its forward recurrence. Since
// a_l ≤ (ρ/R)^l, the series stop where the Laplace series' tail (with the
// l² of the gradient's Φ_l') is below 1e-15 of its sum.
//
// Also: ∫_B G_B(x, y) dy = (1 − a_0(ρ))/k² (it solves (−Δ + k²)v = 1 and
// vanishes on ∂B), and the means over a uniform s on ∂B of the kernel and
// of the kernel times s − c: a_0 and R a_1 e (e the direction of x − c),
// the control variates' exact means.
#ifndef GRIDFREE_CACHE_SCREENED_BALL_SERIES_H
#define GRIDFREE_CACHE_SCREENED_BALL_SERIES_H

#include <gridfree/math/BesselFunctions.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gridfree
{
template <int DIM>
class ScreenedBallSeries
{
public:
  // The coefficients that depend on a point's distance ρ from the centre.
  struct Radial
  {
    int Terms = 0;          // l = 0 .. Terms − 1 (fewer the nearer the centre)
    std::vector<double> A;  // a_l(ρ)
    std::vector<double> B;  // a_l(ρ)/ρ (finite at ρ = 0; 0 for l = 0)
    std::vector<double> D;  // a_l'(ρ)
    std::vector<double> Scratch; // r_l(kρ)
  };

  // The ball's radius R and k = √c; `reach` bounds the points' ρ/R (the
  // number of terms).
  ScreenedBallSeries(double k, double R, double reach)
    : K(k)
    , Radius(R)
  {
    const int terms = TermsFor(std::min(reach, 0.95));
    this->Terms = terms;
    const double z = k * R;
    Ratios(z, terms + 1, this->RatioAtR);
    // c_l from the Wronskian, s_l = k_{l+1}/k_l forward.
    this->C.resize(static_cast<std::size_t>(terms));
    double s;
    if constexpr (DIM == 3)
    {
      s = (1.0 + z) / z;
    }
    else
    {
      s = BesselKScaled(1, z) / BesselKScaled(0, z);
    }
    const double power = DIM == 3 ? z * z : z;
    for (int l = 0; l < terms; ++l)
    {
      if (l > 0)
      {
        s = 1.0 / s + Alpha(l) / z;
      }
      this->C[static_cast<std::size_t>(l)] = 1.0 / (power * (this->RatioAtR[static_cast<std::size_t>(l + 1)] + s));
    }
  }

  int TermCount() const { return this->Terms; }

  // a_l, a_l/ρ and a_l' at distance ρ from the centre (ρ ≤ R).
  void RadialAt(double rho, Radial& out) const
  {
    const int n = std::min(this->Terms, TermsFor(std::min(rho / this->Radius, 0.95)));
    out.Terms = n;
    out.A.assign(static_cast<std::size_t>(n), 0.0);
    out.B.assign(static_cast<std::size_t>(n), 0.0);
    out.D.assign(static_cast<std::size_t>(n), 0.0);
    const double k = this->K;
    const double z = k * rho;
    // r_l(kρ) for l = 1 .. n; q_l = r_l(kρ)/ρ = k/(α_l + kρ r_{l+1}(kρ)).
    std::vector<double>& r = out.Scratch;
    Ratios(z, n + 1, r);
    // a_0 = e^{k(ρ − R)} B(kρ)/B(kR), B the e^{−x}-scaled order-0 function.
    double a = std::exp(k * (rho - this->Radius)) * ScaledBesselOverPower<DIM>(0, z) /
      ScaledBesselOverPower<DIM>(0, k * this->Radius);
    out.A[0] = a;
    for (int l = 1; l < n; ++l)
    {
      const double q = k / (Alpha(l) + z * r[static_cast<std::size_t>(l + 1)]);
      const double ratio = 1.0 / this->RatioAtR[static_cast<std::size_t>(l)];
      out.B[static_cast<std::size_t>(l)] = a * q * ratio;
      a = a * rho * q * ratio;
      out.A[static_cast<std::size_t>(l)] = a;
    }
    // a_l' = k r_{l+1}(kρ) a_l + l a_l/ρ (from i_l' = i_{l+1} + (l/z) i_l).
    for (int l = 0; l < n; ++l)
    {
      const auto i = static_cast<std::size_t>(l);
      out.D[i] = k * r[i + 1] * out.A[i] + l * out.B[i];
    }
  }

  // Σ_l β_l f_l g_l Φ_l(μ) and its μ-derivative, for the coefficient
  // sequences f (and g, if given) over the terms.
  struct AngularSums
  {
    double Value = 0.0;
    double Slope = 0.0; // d/dμ
  };

  // The Poisson kernel |∂B| P(x, s) and its x-gradient, with `radial` at ρ
  // = |x − c|, e the direction of x − c (any unit vector at ρ = 0) and n
  // the direction of s − c.
  double Kernel(const Radial& radial, const Vec<DIM>& e, const Vec<DIM>& n, Vec<DIM>* gradient) const
  {
    const double mu = std::clamp(e.dot(n), -1.0, 1.0);
    double value = 0.0, radialPart = 0.0, angularPart = 0.0;
    Sum(radial.Terms, mu, [&](int l, double phi, double slope) {
      const auto i = static_cast<std::size_t>(l);
      const double beta = Beta(l);
      value += beta * radial.A[i] * phi;
      radialPart += beta * radial.D[i] * phi;
      angularPart += beta * radial.B[i] * slope;
    });
    if (gradient)
    {
      // ∇ρ = e, ∇μ = (n − μ e)/ρ (the 1/ρ is in B).
      *gradient = radialPart * e + angularPart * (n - mu * e);
    }
    return value;
  }

  // H(x, y) and its x-gradient, with `atX` at |x − c| (direction e) and
  // `atY` at |y − c| (direction n).
  double Regular(const Radial& atX, const Radial& atY, const Vec<DIM>& e, const Vec<DIM>& n,
    Vec<DIM>* gradient) const
  {
    const double mu = std::clamp(e.dot(n), -1.0, 1.0);
    double value = 0.0, radialPart = 0.0, angularPart = 0.0;
    // a_l(|x − c|) a_l(|y − c|) falls as the smaller ratio's power.
    Sum(std::min(atX.Terms, atY.Terms), mu, [&](int l, double phi, double slope) {
      const auto i = static_cast<std::size_t>(l);
      const double w = Beta(l) * this->C[i] * atY.A[i];
      value += w * atX.A[i] * phi;
      radialPart += w * atX.D[i] * phi;
      angularPart += w * atX.B[i] * slope;
    });
    const double kappa = DIM == 3 ? this->K / (4.0 * M_PI) : 1.0 / (2.0 * M_PI);
    if (gradient)
    {
      *gradient = kappa * (radialPart * e + angularPart * (n - mu * e));
    }
    return kappa * value;
  }

  // The free-space Green's function G(r) of −Δ + k² and G'(r).
  double FreeSpace(double r, double* derivative) const
  {
    const double k = this->K;
    if constexpr (DIM == 3)
    {
      const double g = std::exp(-k * r) / (4.0 * M_PI * r);
      *derivative = -g * (1.0 + k * r) / r;
      return g;
    }
    else
    {
      const double e = std::exp(-k * r);
      *derivative = -k * BesselKScaled(1, k * r) * e / (2.0 * M_PI);
      return BesselKScaled(0, k * r) * e / (2.0 * M_PI);
    }
  }

  // ∫_B G_B(x, y) dy = (1 − a_0(ρ))/k² at ρ (`radial` at ρ), with a series
  // for small kR where 1 − a_0 would cancel.
  double BallIntegral(double rho, const Radial& radial) const
  {
    const double k = this->K, R = this->Radius;
    if (k * R >= 1.0)
    {
      return (1.0 - radial.A[0]) / (k * k);
    }
    // F(z) = Σ γ_n z^{2n} (i_0 or I_0): (F(kR) − F(kρ))/(k² F(kR)).
    double difference = 0.0, total = 1.0, gamma = 1.0;
    double k2n = 1.0, R2n = 1.0, rho2n = 1.0; // k^{2n−2}, R^{2n}, ρ^{2n}
    for (int m = 1; m < 40; ++m)
    {
      gamma /= DIM == 3 ? (2.0 * m) * (2.0 * m + 1.0) : 4.0 * m * m;
      R2n *= R * R;
      rho2n *= rho * rho;
      const double term = gamma * k2n * (R2n - rho2n);
      difference += term;
      total += gamma * k2n * k * k * R2n;
      k2n *= k * k;
      if (term <= 1e-17 * difference)
      {
        break;
      }
    }
    return difference / total;
  }

  // Its x-gradient, −a_0'(ρ) e/k².
  Vec<DIM> BallIntegralGradient(const Radial& radial, const Vec<DIM>& e) const
  {
    return (-radial.D[0] / (this->K * this->K)) * e;
  }

private:
  static double Alpha(int l) { return 2.0 * l + (DIM - 2); }
  static double Beta(int l) { return DIM == 3 ? 2.0 * l + 1.0 : (l == 0 ? 1.0 : 2.0); }

  // The terms that leave the Laplace series' tail Σ_{l ≥ L} (2l+1) l² t^l
  // (with the gradient's l²) below 1e-15 at t = ρ/R (a_l ≤ t^l).
  static int TermsFor(double t)
  {
    int terms = 2;
    double power = t * t;
    while (terms < 400 &&
      (2.0 * terms + 1.0) * (terms + 1.0) * (terms + 1.0) * power > 1e-15 * (1.0 - t))
    {
      ++terms;
      power *= t;
    }
    return terms;
  }

  // r_l(z) for l = 0 .. last (r_0 unused, 0), by the backward recurrence
  // from well past l and z (the start's error shrinks by ≥ 2 per step).
  static void Ratios(double z, int last, std::vector<double>& r)
  {
    r.assign(static_cast<std::size_t>(last + 1), 0.0);
    const int start = std::max(last, static_cast<int>(std::ceil(0.5 * z))) + 60;
    double next = 0.0;
    for (int l = start; l >= 1; --l)
    {
      next = z / (Alpha(l) + z * next);
      if (l <= last)
      {
        r[static_cast<std::size_t>(l)] = next;
      }
    }
  }

  // Calls visit(l, Φ_l(μ), Φ_l'(μ)) for every term: Legendre polynomials
  // (3D), Chebyshev T_l (2D), with their derivatives by recurrence.
  template <class Visit>
  static void Sum(int terms, double mu, Visit&& visit)
  {
    if constexpr (DIM == 3)
    {
      double p0 = 1.0, p1 = mu, d0 = 0.0, d1 = 1.0;
      visit(0, p0, d0);
      if (terms > 1)
      {
        visit(1, p1, d1);
      }
      for (int l = 2; l < terms; ++l)
      {
        const double p2 = ((2.0 * l - 1.0) * mu * p1 - (l - 1.0) * p0) / l;
        const double d2 = mu * d1 + l * p1; // P_l' = μ P_{l−1}' + l P_{l−1}
        visit(l, p2, d2);
        p0 = p1;
        p1 = p2;
        d1 = d2;
      }
    }
    else
    {
      // T_l and U_{l−1} (T_l' = l U_{l−1}).
      double t0 = 1.0, t1 = mu, u0 = 1.0, u1 = 2.0 * mu;
      visit(0, t0, 0.0);
      if (terms > 1)
      {
        visit(1, t1, 1.0);
      }
      for (int l = 2; l < terms; ++l)
      {
        const double t2 = 2.0 * mu * t1 - t0;
        visit(l, t2, l * u1);
        const double u2 = 2.0 * mu * u1 - u0;
        t0 = t1;
        t1 = t2;
        u0 = u1;
        u1 = u2;
      }
    }
  }

  double K;
  double Radius;
  int Terms = 1;
  std::vector<double> RatioAtR; // r_l(kR), l = 0 .. Terms
  std::vector<double> C;        // c_l
};
} // namespace gridfree

#endif
