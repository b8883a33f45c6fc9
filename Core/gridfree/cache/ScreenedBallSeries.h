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
    // With second-order coefficients (RadialAt's secondOrder), for
    // Hessians; all finite at ρ = 0:
    std::vector<double> D2; // a_l''(ρ)
    std::vector<double> EF; // a_0'/ρ (l = 0); a_l'/ρ − a_l/ρ² (l ≥ 1)
    std::vector<double> F;  // a_l/ρ² (l ≥ 2; 0 for l < 2)
    std::vector<double> Scratch; // r_l(kρ)
  };

  // The ball's radius R and k = √c; `reach` bounds the points' ρ/R (the
  // number of terms).
  ScreenedBallSeries(double k, double R, double reach)
    : K(k)
    , Radius(R)
  {
    // (Enough for Hessians; RadialAt takes fewer where they suffice.)
    const int terms = TermsFor(std::min(reach, 0.95), true);
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

  // a_l, a_l/ρ and a_l' at distance ρ from the centre (ρ ≤ R); with
  // `secondOrder`, also what the Hessians need (Radial::D2, EF, F).
  void RadialAt(double rho, Radial& out, bool secondOrder = false) const
  {
    const int n = std::min(this->Terms, TermsFor(std::min(rho / this->Radius, 0.95), secondOrder));
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
    if (!secondOrder)
    {
      out.D2.clear();
      out.EF.clear();
      out.F.clear();
      return;
    }
    // a_l/ρ² = (a_{l−1}/ρ) q_l /r_l(kR) for l ≥ 2; a_0'/ρ = k q_1 a_0;
    // a_l'/ρ − a_l/ρ² = k r_{l+1}(kρ) a_l/ρ + (l − 1) a_l/ρ²; and a_l''
    // from the radial equation a'' + (DIM − 1) a'/ρ = (k² + l(l + DIM − 2)/ρ²) a.
    out.D2.assign(static_cast<std::size_t>(n), 0.0);
    out.EF.assign(static_cast<std::size_t>(n), 0.0);
    out.F.assign(static_cast<std::size_t>(n), 0.0);
    for (int l = 2; l < n; ++l)
    {
      const auto i = static_cast<std::size_t>(l);
      const double q = k / (Alpha(l) + z * r[i + 1]);
      out.F[i] = out.B[i - 1] * q / this->RatioAtR[i];
    }
    out.EF[0] = k * (k / (Alpha(1) + z * r[2])) * out.A[0];
    out.D2[0] = k * k * out.A[0] - (DIM - 1) * out.EF[0];
    for (int l = 1; l < n; ++l)
    {
      const auto i = static_cast<std::size_t>(l);
      out.EF[i] = k * r[i + 1] * out.B[i] + (l - 1) * out.F[i];
      out.D2[i] = k * k * out.A[i] + (l * (l + DIM - 2.0) - (DIM - 1)) * out.F[i] -
        (DIM - 1) * out.EF[i];
    }
  }

  // Σ_l β_l f_l g_l Φ_l(μ) and its μ-derivative, for the coefficient
  // sequences f (and g, if given) over the terms.
  struct AngularSums
  {
    double Value = 0.0;
    double Slope = 0.0; // d/dμ
  };

  // The Poisson kernel |∂B| P(x, s), its x-gradient and, with `hessian`
  // (and `radial` made with second-order coefficients), its x-Hessian,
  // with `radial` at ρ = |x − c|, e the direction of x − c (any unit
  // vector at ρ = 0) and n the direction of s − c.
  double Kernel(const Radial& radial, const Vec<DIM>& e, const Vec<DIM>& n, Vec<DIM>* gradient,
    Mat<DIM>* hessian = nullptr) const
  {
    return this->Series(radial, radial.Terms, e, n, gradient, hessian,
      [](int l) { return Beta(l); });
  }

  // H(x, y), its x-gradient and, with `hessian` (and `atX` made with
  // second-order coefficients), its x-Hessian, with `atX` at |x − c|
  // (direction e) and `atY` at |y − c| (direction n).
  double Regular(const Radial& atX, const Radial& atY, const Vec<DIM>& e, const Vec<DIM>& n,
    Vec<DIM>* gradient, Mat<DIM>* hessian = nullptr) const
  {
    // a_l(|x − c|) a_l(|y − c|) falls as the smaller ratio's power.
    const double kappa = DIM == 3 ? this->K / (4.0 * M_PI) : 1.0 / (2.0 * M_PI);
    return this->Series(atX, std::min(atX.Terms, atY.Terms), e, n, gradient, hessian,
      [&](int l) { return kappa * Beta(l) * this->C[static_cast<std::size_t>(l)] *
                     atY.A[static_cast<std::size_t>(l)]; });
  }

  // The x-Hessian of a_l(ρ) (e·v) for any vector v: the l = 1 term of a
  // series with Φ_1(μ) = μ, for the means the sphere cache's slope control
  // variate subtracts (R a_1 e·β).
  Mat<DIM> FirstOrderHessian(const Radial& radial, const Vec<DIM>& e, const Vec<DIM>& v) const
  {
    const double mu = e.dot(v);
    const Vec<DIM> m = v - mu * e;
    const Mat<DIM> ee = e * e.transpose();
    const double d2 = radial.Terms > 1 ? radial.D2[1] : 0.0;
    const double ef = radial.Terms > 1 ? radial.EF[1] : 0.0;
    return (d2 * mu) * ee + (ef * mu) * (Mat<DIM>::Identity() - ee) +
      ef * (e * m.transpose() + m * e.transpose());
  }

  // The x-Hessian of a_0(ρ): a_0'' eeᵀ + (a_0'/ρ)(I − eeᵀ).
  Mat<DIM> ZerothOrderHessian(const Radial& radial, const Vec<DIM>& e) const
  {
    const Mat<DIM> ee = e * e.transpose();
    return radial.D2[0] * ee + radial.EF[0] * (Mat<DIM>::Identity() - ee);
  }

  // G''(r) from G(r) and G'(r): G'' + (DIM − 1) G'/r = k² G for r > 0.
  double FreeSpaceSecond(double r, double g, double slope) const
  {
    return this->K * this->K * g - (DIM - 1) * slope / r;
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
  // Σ_l w(l) a_l(ρ) Φ_l(μ) over `terms` terms, its x-gradient
  // Σ w [a_l' Φ_l e + (a_l/ρ) Φ_l' m] (m = n − μ e, ∇μ = m/ρ) and its
  // x-Hessian Σ w [a_l'' Φ_l eeᵀ + (a_l'/ρ Φ_l − a_l/ρ² μ Φ_l')(I − eeᵀ)
  // + (a_l'/ρ − a_l/ρ²) Φ_l' (e mᵀ + m eᵀ) + a_l/ρ² Φ_l'' m mᵀ], written
  // with the coefficients that stay finite at ρ = 0 (Radial::EF, F; the
  // l = 1 term's 1/ρ parts cancel since Φ_1 = μ Φ_1' and Φ_1'' = 0).
  template <class Weight>
  double Series(const Radial& radial, int terms, const Vec<DIM>& e, const Vec<DIM>& n,
    Vec<DIM>* gradient, Mat<DIM>* hessian, const Weight& weight) const
  {
    const double mu = std::clamp(e.dot(n), -1.0, 1.0);
    double value = 0.0, radialPart = 0.0, angularPart = 0.0;
    double cee = 0.0, cP = 0.0, cS = 0.0, cmm = 0.0;
    Sum(terms, mu, [&](int l, double phi, double slope, double curvature) {
      const auto i = static_cast<std::size_t>(l);
      const double w = weight(l);
      value += w * radial.A[i] * phi;
      radialPart += w * radial.D[i] * phi;
      angularPart += w * radial.B[i] * slope;
      if (hessian)
      {
        cee += w * radial.D2[i] * phi;
        cP += w * (radial.EF[i] * phi + radial.F[i] * (phi - mu * slope));
        cS += w * radial.EF[i] * slope;
        cmm += w * radial.F[i] * curvature;
      }
    });
    const Vec<DIM> m = n - mu * e;
    if (gradient)
    {
      // ∇ρ = e, ∇μ = (n − μ e)/ρ (the 1/ρ is in B).
      *gradient = radialPart * e + angularPart * m;
    }
    if (hessian)
    {
      const Mat<DIM> ee = e * e.transpose();
      *hessian = cee * ee + cP * (Mat<DIM>::Identity() - ee) +
        cS * (e * m.transpose() + m * e.transpose()) + cmm * (m * m.transpose());
    }
    return value;
  }

  static double Alpha(int l) { return 2.0 * l + (DIM - 2); }
  static double Beta(int l) { return DIM == 3 ? 2.0 * l + 1.0 : (l == 0 ? 1.0 : 2.0); }

  // The terms that leave the Laplace series' tail Σ_{l ≥ L} (2l+1) l² t^l
  // (with the gradient's l²) below 1e-15 at t = ρ/R (a_l ≤ t^l); with
  // `secondOrder`, the Hessian's tail Σ (2l+1) l⁴ t^{l−2} (its Φ_l'' and
  // a_l/ρ²), so at least l = 2, which stays finite at the centre.
  static int TermsFor(double t, bool secondOrder = false)
  {
    int terms = secondOrder ? 3 : 2;
    double power = secondOrder ? t : t * t;
    const auto tail = [&](double l) {
      return (2.0 * l + 1.0) * (l + 1.0) * (l + 1.0) * (secondOrder ? (l + 1.0) * (l + 1.0) : 1.0);
    };
    while (terms < 400 && tail(terms) * power > 1e-15 * (1.0 - t))
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

  // Calls visit(l, Φ_l(μ), Φ_l'(μ), Φ_l''(μ)) for every term: Legendre
  // polynomials (3D), Chebyshev T_l (2D), with their derivatives by
  // recurrence (none divides by 1 − μ², so μ = ±1 is no special case).
  template <class Visit>
  static void Sum(int terms, double mu, Visit&& visit)
  {
    if constexpr (DIM == 3)
    {
      // P_l' = μ P_{l−1}' + l P_{l−1}, P_l'' = μ P_{l−1}'' + (l + 1) P_{l−1}'.
      double p0 = 1.0, p1 = mu, d1 = 1.0, c1 = 0.0;
      visit(0, p0, 0.0, 0.0);
      if (terms > 1)
      {
        visit(1, p1, d1, c1);
      }
      for (int l = 2; l < terms; ++l)
      {
        const double p2 = ((2.0 * l - 1.0) * mu * p1 - (l - 1.0) * p0) / l;
        const double d2 = mu * d1 + l * p1;
        const double c2 = mu * c1 + (l + 1.0) * d1;
        visit(l, p2, d2, c2);
        p0 = p1;
        p1 = p2;
        d1 = d2;
        c1 = c2;
      }
    }
    else
    {
      // T_l = 2μ T_{l−1} − T_{l−2}, differentiated once and twice.
      double t0 = 1.0, t1 = mu, d0 = 0.0, d1 = 1.0, c0 = 0.0, c1 = 0.0;
      visit(0, t0, d0, c0);
      if (terms > 1)
      {
        visit(1, t1, d1, c1);
      }
      for (int l = 2; l < terms; ++l)
      {
        const double t2 = 2.0 * mu * t1 - t0;
        const double d2 = 2.0 * t1 + 2.0 * mu * d1 - d0;
        const double c2 = 4.0 * d1 + 2.0 * mu * c1 - c0;
        visit(l, t2, d2, c2);
        t0 = t1;
        t1 = t2;
        d0 = d1;
        d1 = d2;
        c0 = c1;
        c1 = c2;
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
