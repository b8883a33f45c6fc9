// Second-derivative kernels of a ball B(x, R) for the Hessian estimator
// (paper Sec. 3.3, Eqn. 15 and its integration-by-parts form, App. B.2.2;
// FORMULAS.md §5, which corrects the paper's constants and sign):
//
//   ∇²u(x) = mean_∂B[ u (α ν νᵀ + β I) ]
//            − ∫_B [ ∇f(y) ⊗ ∇_x G(x, y) − f(y) (ψ(r) d dᵀ − φ(r) I) ] dy
//
// for Δu − c u = f (c = 0: Laplace/Poisson), d = y − x, r = |d|, ν = d/R.
//
// Harmonic (c = 0), FORMULAS.md §5:
//   α = n(n+2)/R²,  β = −(n+2)/R²,
//   ψ = n/(|S| R^{n+2}),  φ = (r² − R²)/(|S| R^{n+2}).
//
// Yukawa (c > 0, s = √c, z = sR). FORMULAS.md covers only the harmonic
// Hessian, so the screened constants are derived here the same way and are
// checked by quadrature in TestGreensFunctionHessians. Write I_ℓ for the
// modified Bessel function I_ℓ (2D) or the modified spherical Bessel function
// i_ℓ (3D), and Φ(r) = K0(sr)/(2π) or e^{−sr}/(4π r) for the free-space kernel.
// - Boundary: requiring mean_∂B[e^{k·y}(α ν νᵀ + β I)] = k kᵀ for every
//   solution e^{k·y}, |k| = s, gives α = s²/I_2(z), β = −s² I_1(z)/(z I_0(z) I_2(z))
//   (the same argument gives FORMULAS.md's C = 1/I_0(z) and κ = s/I_1(z)).
// - Source: G_B = Φ(y − x) − H(x, y), where the regular part H solves
//   (Δ_y − c)H = 0 with H = Φ on ∂B. Its x-derivatives at the centre solve the
//   same problem with data −∂Φ (degree 1 on the sphere) and ∂²Φ (degrees 0
//   and 2), extended inside by I_ℓ(sr)/I_ℓ(z). Integrating ∫ f ∂²_y Φ by parts
//   leaves M = (∂_y + ∂_x) ∂_x H = ψ d dᵀ − φ I with, for A = Φ''(R) − Φ'(R)/R,
//     ψ(r) = (I_2(sr)/r²) · [A/I_2(z) − s Φ'(R)/I_1(z)],
//     φ(r) = Φ'(R) I_1(sr)/(r I_1(z)) + (A/n) I_2(sr)/I_2(z)
//            − (A/n + Φ'(R)/R) I_0(sr)/I_0(z),
//   which reduce to the harmonic ψ and φ as c → 0. ∫_B M dy = (C/n) I (the
//   Hessian of ∫_B G_c at the centre is −(C/n) I), so a constant can be
//   subtracted from f as a control variate and added back exactly.
// - Point and curve sources need ∇²_x G_B(x, x + d) away from the pole:
//   Hess Φ(d) − ∂²_x H(x, x + d), with Hess Φ = (Φ'' − Φ'/r) d̂ d̂ᵀ + (Φ'/r) I.
//
// Every Bessel function enters scaled (BesselFunctions.h), so the kernels stay
// finite for any z; they are built once per first ball, never per step.
#ifndef GRIDFREE_GREENS_GREENS_FUNCTION_HESSIANS_H
#define GRIDFREE_GREENS_GREENS_FUNCTION_HESSIANS_H

#include <gridfree/sampling/BallSampling.h>
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/math/Vector.h>

#include <cmath>

namespace gridfree
{
template <int DIM>
class BallHessianKernels
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");

public:
  // c = 0 gives the harmonic kernels.
  BallHessianKernels(double radius, double c)
    : R(radius)
    , S(c > 0.0 ? std::sqrt(c) : 0.0)
    , Z(S * radius)
    , SphereArea(UnitSphereArea<DIM>())
  {
    const double n = DIM;
    if (!(c > 0.0))
    {
      this->Alpha = n * (n + 2.0) / (radius * radius);
      this->Beta = -(n + 2.0) / (radius * radius);
      this->Weight = 1.0;
      return;
    }
    const double z = this->Z;
    const double expMinusZ = std::exp(-z);
    this->B0 = ScaledBesselOverPower<DIM>(0, z);
    this->B1 = ScaledBesselOverPower<DIM>(1, z);
    this->B2 = ScaledBesselOverPower<DIM>(2, z);
    // I_ℓ(z) = e^{z} z^ℓ B_ℓ(z).
    const double s2 = c;
    this->Alpha = s2 * expMinusZ / (z * z * this->B2);
    this->Beta = -s2 * expMinusZ * this->B1 / (z * z * this->B0 * this->B2);
    this->Weight = expMinusZ / this->B0;
    // Φ'(R) = e^{−z} Fp and A = e^{−z} Aa.
    if (DIM == 2)
    {
      this->Fp = -this->S * BesselKScaled(1, z) / (2.0 * M_PI);
      this->Aa = s2 * BesselKScaled(2, z) / (2.0 * M_PI);
    }
    else
    {
      this->Fp = -(1.0 + z) / (4.0 * M_PI * radius * radius);
      this->Aa = (z * z + 3.0 * z + 3.0) / (4.0 * M_PI * radius * radius * radius);
    }
  }

  double Radius() const { return this->R; }

  // ∇²u(x) boundary term: mean_∂B[u (α ν νᵀ + β I)], ν the unit normal.
  double BoundaryNormalWeight() const { return this->Alpha; }
  double BoundaryIdentityWeight() const { return this->Beta; }

  // mean_∂B[α ν νᵀ + β I] = (α/n + β) I: zero for c = 0, not for c > 0, so a
  // constant control variate on the boundary term must add this back.
  double BoundaryKernelMean() const { return this->Alpha / DIM + this->Beta; }

  // C of the value formula (1/I_0(z)), for the regular part's integral.
  double BoundaryWeight() const { return this->Weight; }

  // ∫_B (ψ d dᵀ − φ I) dy = (C/n) I.
  double RegularPartIntegral() const { return this->Weight / DIM; }

  // ψ(r) and φ(r) of M = ψ d dᵀ − φ I, 0 <= r <= R.
  void RegularPart(double r, double& psi, double& phi) const
  {
    const double n = DIM;
    const double rn2 = std::pow(this->R, DIM + 2);
    if (this->S == 0.0)
    {
      psi = n / (this->SphereArea * rn2);
      phi = (r * r - this->R * this->R) / (this->SphereArea * rn2);
      return;
    }
    const double sr = this->S * r;
    const double z = this->Z;
    const double rho = r / this->R;
    const double b0 = ScaledBesselOverPower<DIM>(0, sr);
    const double b1 = ScaledBesselOverPower<DIM>(1, sr);
    const double b2 = ScaledBesselOverPower<DIM>(2, sr);
    // I_2(sr)/r² = s² e^{sr} b2; A/I_2(z) = e^{−2z} Aa/(z² B2);
    // sΦ'(R)/I_1(z) = e^{−2z} s Fp/(z B1).
    const double decay = std::exp(sr - 2.0 * z);
    psi = this->S * this->S * decay * b2 *
      (this->Aa / (z * z * this->B2) - this->S * this->Fp / (z * this->B1));
    phi = decay *
      (this->Fp * b1 / (this->B1 * this->R) + (this->Aa / n) * rho * rho * b2 / this->B2 -
        (this->Aa / n + this->Fp / this->R) * b0 / this->B0);
  }

  Mat<DIM> RegularPartMatrix(const Vec<DIM>& d) const
  {
    double psi = 0.0, phi = 0.0;
    this->RegularPart(d.norm(), psi, phi);
    return psi * d * d.transpose() - phi * Mat<DIM>::Identity();
  }

  // ∇²_x G_B(x, x + d) for 0 < |d| < R (zero outside the ball).
  Mat<DIM> PoleHessian(const Vec<DIM>& d) const
  {
    const double r = d.norm();
    const double n = DIM;
    if (!(r > 0.0) || r >= this->R)
    {
      return Mat<DIM>::Zero();
    }
    const Vec<DIM> e = d / r;
    const Mat<DIM> ee = e * e.transpose();
    const Mat<DIM> identity = Mat<DIM>::Identity();
    if (this->S == 0.0)
    {
      const double rn = std::pow(r, DIM);
      const double rn2 = std::pow(this->R, DIM + 2);
      return (n * ee - identity) / (this->SphereArea * rn) -
        (n * d * d.transpose() - r * r * identity) / (this->SphereArea * rn2);
    }
    const double s = this->S;
    const double sr = s * r;
    const double z = this->Z;
    // Free-space part: (Φ'' − Φ'/r) and Φ'/r at r.
    double radial = 0.0, tangential = 0.0;
    if (DIM == 2)
    {
      const double e1 = std::exp(-sr);
      radial = s * s * e1 * BesselKScaled(2, sr) / (2.0 * M_PI);
      tangential = -s * e1 * BesselKScaled(1, sr) / (2.0 * M_PI * r);
    }
    else
    {
      const double e1 = std::exp(-sr);
      radial = e1 * (sr * sr + 3.0 * sr + 3.0) / (4.0 * M_PI * r * r * r);
      tangential = -e1 * (1.0 + sr) / (4.0 * M_PI * r * r * r);
    }
    // Regular part ∂²_x H = e^{−2z+sr}[Aa (d̂d̂ − I/n) ρ² b2/B2 + (Aa/n + Fp/R) b0/B0 I].
    const double rho = r / this->R;
    const double decay = std::exp(sr - 2.0 * z);
    const double b0 = ScaledBesselOverPower<DIM>(0, sr);
    const double b2 = ScaledBesselOverPower<DIM>(2, sr);
    const Mat<DIM> regular = decay *
      (this->Aa * rho * rho * (b2 / this->B2) * (ee - identity / n) +
        (this->Aa / n + this->Fp / this->R) * (b0 / this->B0) * identity);
    return radial * ee + tangential * identity - regular;
  }

private:
  double R;
  double S;
  double Z;
  double SphereArea;
  double Alpha = 0.0;
  double Beta = 0.0;
  double Weight = 1.0;
  // Yukawa only: B_ℓ(z) = e^{−z} I_ℓ(z)/z^ℓ, Φ'(R) = e^{−z} Fp, A = e^{−z} Aa.
  double B0 = 1.0;
  double B1 = 1.0;
  double B2 = 1.0;
  double Fp = 0.0;
  double Aa = 0.0;
};
} // namespace gridfree

#endif
