// Dirichlet Green's functions of a ball B(x, R) in 2D and 3D, with the
// constants of the ball mean-value formulas and exact samplers of the
// normalized kernel (paper App. B, Eqns. 7-8; formulas from FORMULAS.md, which
// corrects the paper's source sign, screened gradient and 3D radial density).
//
// Both classes share one interface so an estimator can be templated on either:
//
//   u(x)  = BoundaryWeight() · mean_∂B u − ∫_B f G dy                  (value)
//   ∇u(x) = GradientWeight() · mean_∂B [u ν] − ∫_B f ∇G dy            (gradient)
//
// for Δu = f (harmonic) or Δu − c u = f (Yukawa), with ν = (y − x)/R. One
// object is built per walk step, so everything depending only on R and c is
// computed in the constructor and Value() stays a few function calls.
#ifndef GRIDFREE_GREENS_GREENS_FUNCTIONS_H
#define GRIDFREE_GREENS_GREENS_FUNCTIONS_H

#include <gridfree/sampling/BallSampling.h>
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gridfree
{
namespace greens_detail
{
// Uniform in the open interval (0, 1). The samplers take logarithms of it and
// must return radii r > 0, where Value() and Density() are finite.
inline double OpenUniform(RandomStream& rng)
{
  double u = rng.NextDouble();
  while (u == 0.0)
  {
    u = rng.NextDouble();
  }
  return u;
}

// Exact sampler of the harmonic radial density ∝ r^{n−1} G(r) on (0, R)
// (FORMULAS.md §6; the paper's App. B 3D density "r² sin θ" is wrong):
// 2D p(r) = 4r log(R/r)/R², (r/R)² is a product of two uniforms;
// 3D p(r) = 6r(R − r)/R³, r/R ~ Beta(2, 2), the median of three uniforms.
template <int DIM>
double SampleHarmonicRadius(double radius, RandomStream& rng)
{
  if (DIM == 2)
  {
    return radius * std::sqrt(OpenUniform(rng) * OpenUniform(rng));
  }
  const double a = OpenUniform(rng);
  const double b = OpenUniform(rng);
  const double c = OpenUniform(rng);
  return radius * std::max(std::min(a, b), std::min(std::max(a, b), c));
}
} // namespace greens_detail

// Green's function of Δ on B(x, R) with G = 0 on ∂B and −Δ_y G = δ_x
// (FORMULAS.md §1, paper App. B.1).
template <int DIM>
class HarmonicGreensFunction
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");

public:
  explicit HarmonicGreensFunction(double radius)
    : R(radius)
    , InvRadiusPowN(1.0 / PowerOf<DIM>(radius))
  {
  }

  double Radius() const { return this->R; }

  // G2 = log(R/r)/(2π), G3 = (R − r)/(4π r R) (FORMULAS.md §1, App. B.1).
  // r = |y − x|; 0 outside the ball, +inf at the pole.
  double Value(double r) const
  {
    if (r >= this->R)
    {
      return 0.0;
    }
    if (r <= 0.0)
    {
      return std::numeric_limits<double>::infinity();
    }
    if (DIM == 2)
    {
      return std::log(this->R / r) / (2.0 * M_PI);
    }
    return (this->R - r) / (4.0 * M_PI * r * this->R);
  }

  // ∫_B G dy = R²/(2n) (FORMULAS.md §1, App. B.1).
  double Integral() const { return this->R * this->R / (2.0 * DIM); }

  // Mean-value property: u(x) = mean_∂B u − ∫_B f G (FORMULAS.md §2, Eqn. 7
  // with the sign corrected for Δu = f).
  double BoundaryWeight() const { return 1.0; }

  // ∇u(x) = (n/R) mean_∂B[u ν] − ∫_B f ∇G (FORMULAS.md §4, Eqns. 12-13).
  double GradientWeight() const { return DIM / this->R; }

  // ∇_x G at the centre, d = y − x: d/|S| · (1/r^n − 1/R^n) (FORMULAS.md §1,
  // App. B.1). The −1/R^n is the image term: without it ∇u is ~90% off.
  // Zero outside the ball and at the pole (odd kernel, principal value).
  Vec<DIM> Gradient(const Vec<DIM>& d) const
  {
    const double r = d.norm();
    if (r >= this->R || r <= 0.0)
    {
      return Vec<DIM>::Zero();
    }
    const double invRPowN = DIM == 2 ? 1.0 / (r * r) : 1.0 / (r * r * r);
    return d * ((invRPowN - this->InvRadiusPowN) / UnitSphereArea<DIM>());
  }

  // |∇_x G| at distance r, so that ∇G = GradientMagnitude(|d|) · d/|d|:
  // (1/r^{n−1} − r/R^n)/|S|, positive inside the ball and 0 on ∂B.
  double GradientMagnitude(double r) const
  {
    if (r >= this->R || r <= 0.0)
    {
      return 0.0;
    }
    const double invRPowNMinus1 = DIM == 2 ? 1.0 / r : 1.0 / (r * r);
    return (invRPowNMinus1 - r * this->InvRadiusPowN) / UnitSphereArea<DIM>();
  }

  // Volume pdf of SampleOffset at |d| = r: G/∫G (App. B, p_G).
  double Density(double r) const { return this->Value(r) / this->Integral(); }

  // Radius with density ∝ r^{n−1} G(r) (FORMULAS.md §6, harmonic case).
  double SampleRadius(RandomStream& rng) const
  {
    return greens_detail::SampleHarmonicRadius<DIM>(this->R, rng);
  }

  // d = y − x with volume pdf Density(|d|): then ∫_B f G ≈ Integral()·f(x + d).
  Vec<DIM> SampleOffset(RandomStream& rng) const
  {
    const Vec<DIM> direction = SampleUnitSphere<DIM>(rng);
    return this->SampleRadius(rng) * direction;
  }

private:
  double R;
  double InvRadiusPowN;
};

// Green's function of Δ − c (c > 0) on B(x, R) with G_c = 0 on ∂B and
// −(Δ_y − c) G_c = δ_x: the Yukawa potential (FORMULAS.md §3, paper App. B.2).
// With s = sqrt(c), z = sR, all Bessel functions enter in scaled form so the
// object stays finite and accurate for any z (paper's unscaled forms give NaN
// at z = 800), and the small-z branches are series without cancellation, so
// c → 0 recovers the harmonic values smoothly.
template <int DIM>
class YukawaGreensFunction
{
  static_assert(DIM == 2 || DIM == 3, "2D or 3D only");

public:
  YukawaGreensFunction(double radius, double c)
    : R(radius)
    , Coefficient(c)
    , S(std::sqrt(c))
    , Z(std::sqrt(c) * radius)
  {
    const double z = this->Z;
    const double expMinusZ = std::exp(-z);
    // The harmonic proposal's acceptance 2n(1 − C)/z² beats the free-space
    // proposal's 1 − C exactly when z² <= 2n (FORMULAS.md §6).
    this->UseHarmonicProposal = z * z <= 2.0 * DIM;
    if (DIM == 2)
    {
      const double i0 = BesselI0Scaled(z);
      const double i1 = BesselI1Scaled(z);
      this->RatioK0I0 = BesselK0Scaled(z) / i0;
      this->RatioK1I1 = BesselK1Scaled(z) / i1;
      // C2 = 1/I0(z), κ2 = s/I1(z) (FORMULAS.md §3 stable forms; App. B.2.1).
      this->Weight = expMinusZ / i0;
      this->Kappa = this->S * expMinusZ / i1;
      if (z < 1.0)
      {
        // (1 − 1/I0)/c = R² S/(1 + z² S) with S = (I0 − 1)/z² =
        // Σ_{k≥1} (z²/4)^{k−1}/(4 (k!)²): no 1 − C cancellation, exact at z = 0.
        const double q = 0.25 * z * z;
        double term = 0.25;
        double sum = term;
        for (int k = 1; k < 30 && term > 1e-17 * sum; ++k)
        {
          term *= q / ((k + 1.0) * (k + 1.0));
          sum += term;
        }
        this->IntegralValue = radius * radius * sum / (1.0 + z * z * sum);
      }
    }
    else
    {
      this->Expm1TwoZ = std::expm1(-2.0 * z);
      this->SphericalI1Z = SphericalBesselI1Scaled(z);
      // C3 = z/sinh z, κ3 = s/i1(z) (FORMULAS.md §3 stable forms; App. B.2.1).
      this->Weight = -2.0 * z * expMinusZ / this->Expm1TwoZ;
      this->Kappa = this->S * expMinusZ / this->SphericalI1Z;
      if (z < 1.0)
      {
        // sinh z / z = T = 1 + z² T1 with T1 = Σ_{k≥1} z^{2k−2}/(2k+1)!, so
        // (1 − C)/c = R² T1/T without cancellation, exact at z = 0.
        double term = 1.0 / 6.0;
        double sum = term;
        for (int k = 1; k < 30 && term > 1e-17 * sum; ++k)
        {
          term *= z * z / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
          sum += term;
        }
        this->IntegralValue = radius * radius * sum / (1.0 + z * z * sum);
      }
    }
    if (z >= 1.0)
    {
      // ∫_B G_c = (1 − C)/c (FORMULAS.md §3); here 1 − C >= 0.2.
      this->IntegralValue = (1.0 - this->Weight) / c;
    }
  }

  double Radius() const { return this->R; }
  double Screening() const { return this->Coefficient; }

  // G_c2 = e^{−sr}/(2π)·[k0e(sr) − i0e(sr)·k0e(z)/i0e(z)·e^{−2s(R−r)}],
  // G_c3 = e^{−sr}·expm1(−2s(R − r))/(4π r·expm1(−2z)) (FORMULAS.md §3 stable
  // forms of App. B.2). 0 outside the ball, +inf at the pole.
  double Value(double r) const
  {
    if (r >= this->R)
    {
      return 0.0;
    }
    if (r <= 0.0)
    {
      return std::numeric_limits<double>::infinity();
    }
    const double sr = this->S * r;
    const double boundaryDecay = -2.0 * this->S * (this->R - r);
    if (DIM == 2)
    {
      const double bracket =
        BesselK0Scaled(sr) - BesselI0Scaled(sr) * this->RatioK0I0 * std::exp(boundaryDecay);
      // G_c >= 0 (maximum principle); clamp rounding just inside ∂B.
      return std::max(0.0, std::exp(-sr) * bracket / (2.0 * M_PI));
    }
    return std::exp(-sr) * std::expm1(boundaryDecay) / (4.0 * M_PI * r * this->Expm1TwoZ);
  }

  // ∫_B G_c dy = (1 − C)/c (FORMULAS.md §3; App. B.2), → R²/(2n) as c → 0.
  double Integral() const { return this->IntegralValue; }

  // C in u(x) = C·mean_∂B u − ∫_B f G_c: C2 = 1/I0(z), C3 = z/sinh z
  // (FORMULAS.md §3, App. B.2.1; C = minus the flux of G_c through ∂B).
  double BoundaryWeight() const { return this->Weight; }

  // κ in ∇u(x) = κ·mean_∂B[u ν] − ∫_B f ∇G_c: κ2 = s/I1(z), κ3 = s/i1(z)
  // (FORMULAS.md §3; the paper implies n/R, which only holds as c → 0).
  double GradientWeight() const { return this->Kappa; }

  // ∇_x G_c at the centre, d = y − x (FORMULAS.md §3, corrected App. B.2):
  // 2D d·s/(2π r)·e^{−sr}[k1e(sr) − k1e(z)/i1e(z)·i1e(sr)·e^{−2s(R−r)}],
  // 3D d·e^{−sr}[(1 + sr) − (1 + z)(r/R)²·e^{−2s(R−r)}·i1s(sr)/i1s(z)]/(4π r³).
  // Zero outside the ball and at the pole (odd kernel, principal value).
  Vec<DIM> Gradient(const Vec<DIM>& d) const
  {
    const double r = d.norm();
    if (r >= this->R || r <= 0.0)
    {
      return Vec<DIM>::Zero();
    }
    const double sr = this->S * r;
    const double boundaryDecay = std::exp(-2.0 * this->S * (this->R - r));
    if (DIM == 2)
    {
      const double bracket =
        BesselK1Scaled(sr) - this->RatioK1I1 * BesselI1Scaled(sr) * boundaryDecay;
      return d * (this->S * std::exp(-sr) * bracket / (2.0 * M_PI * r));
    }
    const double rho = r / this->R;
    const double bracket = (1.0 + sr) -
      (1.0 + this->Z) * rho * rho * boundaryDecay * SphericalBesselI1Scaled(sr) /
        this->SphericalI1Z;
    return d * (std::exp(-sr) * bracket / (4.0 * M_PI * r * r * r));
  }

  // |∇_x G_c| at distance r: ∇G_c = GradientMagnitude(|d|) · d/|d|.
  double GradientMagnitude(double r) const
  {
    if (r >= this->R || r <= 0.0)
    {
      return 0.0;
    }
    Vec<DIM> d = Vec<DIM>::Zero();
    d[0] = r;
    return this->Gradient(d)[0];
  }

  // Volume pdf of SampleOffset at |d| = r: G_c/∫G_c (FORMULAS.md §6).
  double Density(double r) const { return this->Value(r) / this->IntegralValue; }

  // Radius with density ∝ r^{n−1} G_c(r), by rejection (FORMULAS.md §6):
  // G_c <= G and G_c <= Φ_c, so either kernel's exact sampler is a proposal.
  // Worst acceptance is ~0.56 at the switch, z² = 2n. So kMaxProposals
  // rejections in a row (probability below 0.44^1000, zero in double) only
  // happen for a ball whose radius or coefficient is NaN or infinite, where
  // every test fails: the radius is then NaN (the walk's sample becomes NaN
  // and is seen) instead of an endless loop.
  static constexpr int kMaxProposals = 1000;

  double SampleRadius(RandomStream& rng) const
  {
    if (this->UseHarmonicProposal)
    {
      for (int proposal = 0; proposal < kMaxProposals; ++proposal)
      {
        const double r = greens_detail::SampleHarmonicRadius<DIM>(this->R, rng);
        const double harmonic = HarmonicGreensFunction<DIM>(this->R).Value(r);
        if (harmonic > 0.0 && rng.NextDouble() * harmonic < this->Value(r))
        {
          return r;
        }
      }
      return std::numeric_limits<double>::quiet_NaN();
    }
    for (int proposal = 0; proposal < kMaxProposals; ++proposal)
    {
      // Free-space radial densities: 2D r K0(sr) (s r/2 is the geometric mean
      // of two Exp(1)), 3D r e^{−sr} (Gamma(2, 1/s)).
      const double a = std::log(greens_detail::OpenUniform(rng));
      const double b = std::log(greens_detail::OpenUniform(rng));
      const double r = DIM == 2 ? 2.0 * std::sqrt(a * b) / this->S : -(a + b) / this->S;
      if (r >= this->R)
      {
        continue;
      }
      if (rng.NextDouble() < this->FreeSpaceRatio(r))
      {
        return r;
      }
    }
    return std::numeric_limits<double>::quiet_NaN();
  }

  // d = y − x with volume pdf Density(|d|): then ∫_B f G_c ≈ Integral()·f(x + d).
  Vec<DIM> SampleOffset(RandomStream& rng) const
  {
    const Vec<DIM> direction = SampleUnitSphere<DIM>(rng);
    return this->SampleRadius(rng) * direction;
  }

private:
  // G_c/Φ_c in [0, 1] for 0 < r < R, Φ_c the free-space kernel
  // (FORMULAS.md §6): 3D expm1(−2s(R − r))/expm1(−2z),
  // 2D 1 − I0(sr)K0(z)/(I0(z)K0(sr)) in scaled form.
  double FreeSpaceRatio(double r) const
  {
    const double boundaryDecay = -2.0 * this->S * (this->R - r);
    if (DIM == 2)
    {
      const double sr = this->S * r;
      return 1.0 -
        BesselI0Scaled(sr) * this->RatioK0I0 * std::exp(boundaryDecay) / BesselK0Scaled(sr);
    }
    return std::expm1(boundaryDecay) / this->Expm1TwoZ;
  }

  double R;
  double Coefficient;
  double S;
  double Z;
  double Weight = 1.0;
  double Kappa = 0.0;
  double IntegralValue = 0.0;
  bool UseHarmonicProposal = true;
  // 2D: k0e(z)/i0e(z) and k1e(z)/i1e(z).
  double RatioK0I0 = 0.0;
  double RatioK1I1 = 0.0;
  // 3D: expm1(−2z) and e^{−z} i1(z).
  double Expm1TwoZ = 0.0;
  double SphericalI1Z = 0.0;
};
} // namespace gridfree

#endif
