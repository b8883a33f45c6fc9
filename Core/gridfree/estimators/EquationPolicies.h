// What sets the equations apart inside a walk (paper Sec. 2–4), as small
// policy types the walk is compiled for, instead of tests of the equation
// spread over every step:
//   - the Green's function of each ball (harmonic, or Yukawa for the
//     screened Poisson equation: FORMULAS.md §1–§3, paper App. A);
//   - the step radius (the biharmonic walk keeps the largest balls);
//   - what multiplies the walk at each step (the screened equation's
//     boundary weight C, taken by roulette far from everything);
//   - what the walk does beyond the far sphere (an exterior strategy for
//     the harmonic equations, escape for the others);
//   - the terminal value (the biharmonic walk's Σ∫G·h and its Δu).
// Laplace and Poisson share one policy: the Poisson walk's sources are
// the problem's, not the equation's.
#ifndef gridfree_estimators_EquationPolicies_h
#define gridfree_estimators_EquationPolicies_h

#include <gridfree/greens/GreensFunctions.h>

namespace gridfree
{
namespace equations
{
// Δu = f (f = 0: Laplace).
template <int DIM>
struct Harmonic
{
  // Walks far away are returned or ended by Russian roulette (Sec. 2.6).
  static constexpr bool HasExteriorStrategy = true;
  // Every step multiplies the walk by the ball's boundary weight.
  static constexpr bool WeightsSteps = false;
  static constexpr bool IsBiharmonic = false;

  HarmonicGreensFunction<DIM> Green(double radius) const
  {
    return HarmonicGreensFunction<DIM>(radius);
  }
  double ScreeningCoefficient() const { return 0.0; }
};

// Δu − c·u = f.
template <int DIM>
struct Screened
{
  static constexpr bool HasExteriorStrategy = false;
  static constexpr bool WeightsSteps = true;
  static constexpr bool IsBiharmonic = false;

  double Coefficient; // c > 0

  YukawaGreensFunction<DIM> Green(double radius) const
  {
    return YukawaGreensFunction<DIM>(radius, this->Coefficient);
  }
  double ScreeningCoefficient() const { return this->Coefficient; }
};

// Δ²u = 0 with u = g and Δu = h on the boundary.
template <int DIM>
struct Biharmonic
{
  static constexpr bool HasExteriorStrategy = false;
  static constexpr bool WeightsSteps = false;
  static constexpr bool IsBiharmonic = true;

  HarmonicGreensFunction<DIM> Green(double radius) const
  {
    return HarmonicGreensFunction<DIM>(radius);
  }
  double ScreeningCoefficient() const { return 0.0; }

  // Tree walking: u(x₀) gets −Σ_k ∫_{B_k} G · v(x_k), v = Δu estimated by
  // h at the walk's end; Δu(x₀) = v(x₀) is a Laplace estimate with data h.
  // `values` holds g then h at the end point; `nc` components each.
  static void Finish(double* sample, const double* values, double ballIntegrals, int nc)
  {
    for (int c = 0; c < nc; ++c)
    {
      const double h = values[nc + c];
      sample[c] -= ballIntegrals * h;
      sample[nc + c] = h;
    }
  }
};
} // namespace equations
} // namespace gridfree

#endif
