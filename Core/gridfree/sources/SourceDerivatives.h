// Source terms of the gradient and Hessian estimators over the first ball
// B(x, R) of a walk (paper Eqns. 14–15 and the integration-by-parts form of
// Sec. 3.3; FORMULAS.md §4–§5 for the kernels and the corrected sign):
//
//   ∇u(x)  ∋ −∫_B f ∇G dy
//   ∇²u(x) ∋ −∫_B [∇f ⊗ ∇G − f (ψ d dᵀ − φ I)] dy      (d = y − x)
//
// This class estimates the integrals ∫ f ∇G and ∫ [∇f ⊗ ∇G − f M] (the
// caller subtracts them). Three choices keep the variance finite where the
// textbook one-sample estimators do not:
// - ∇G ~ 1/r^{n−1} is odd, so the one-sample estimate with y ~ U(B) or
//   y ~ G/∫G has infinite variance in 3D. Samples come in antithetic pairs
//   y = x ± d: the kernel sees ½(f(x + d) − f(x − d)) ~ r |∇f|, which makes the
//   variance finite and removes any constant part of f exactly — the exact
//   form of the paper's running-source-mean control variate for the gradient
//   (Sec. 4.1.2).
// - The radius is drawn from the mixture of FirstBallRadius.h, which cancels
//   the pole, covers the rim (where M does not vanish) and follows strong
//   screening's decay; its weight keeps any kernel unbiased.
// - In the Hessian's f·M term, a running mean f̄ of f over the first ball is
//   subtracted and its exact integral f̄ (C/n) I added back (Sec. 4.1.3 in
//   spirit; ∫_B M = (C/n) I, GreensFunctionHessians.h).
// Point sources add s ∇G(z − x) and s ∇²_x G(z − x) exactly; curve sources
// add one sample L·s(z) of the same kernels (Sec. 4.2.2).
#ifndef GRIDFREE_SOURCES_SOURCE_DERIVATIVES_H
#define GRIDFREE_SOURCES_SOURCE_DERIVATIVES_H

#include <gridfree/sampling/BallSampling.h>
#include <gridfree/sampling/FirstBallRadius.h>
#include <gridfree/greens/GreensFunctionHessians.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/sampling/SphereSampling.h>
#include <gridfree/math/Vector.h>

#include <cmath>
#include <vector>

namespace gridfree
{
template <int DIM>
class SourceDerivativeIntegrator
{
public:
  SourceDerivativeIntegrator(
    int components, VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
    : Components(components)
    , Volume(volume)
    , Concentrated(concentrated)
    , FPlus(components)
    , FMinus(components)
    , GradPlus(components * DIM)
    , GradMinus(components * DIM)
    , Strength(components)
  {
  }

  bool Active() const { return this->Volume || !this->Concentrated.Empty(); }

  // Adds one-sample estimates over B(x, green.Radius()) of
  //   ∫ f ∇G            to gradient (Components() × DIM, component-major), and,
  //   when hessian is not null and kernels is the ball's BallHessianKernels,
  //   ∫ [∇f ⊗ ∇G − f M] to hessian (Components() × DIM × DIM, row-major per
  //   component, symmetrized), using fBar (Components(); null: no control)
  //   as the control variate of the f·M term.
  // Writes the symmetric volume sample ½(f(x + d) + f(x − d)) into fSample
  // (0 without a volume source), for the caller's running mean f̄.
  template <class Green>
  void Accumulate(const Vec<DIM>& x, const Green& green, const BallHessianKernels<DIM>* kernels,
    double screening, RandomStream& rng, const double* fBar, double* gradient, double* hessian,
    double* fSample)
  {
    const int nc = this->Components;
    const double radius = green.Radius();
    const bool wantHessian = hessian != nullptr && kernels != nullptr;
    for (int c = 0; c < nc; ++c)
    {
      fSample[c] = 0.0;
    }
    if (this->Volume)
    {
      const double z = std::sqrt(std::max(screening, 0.0)) * radius;
      const double r = FirstBallRadius<DIM>::Sample(radius, z, rng);
      const Vec<DIM> omega = SampleUnitSphere<DIM>(rng);
      const Vec<DIM> d = r * omega;
      const double weight = FirstBallRadius<DIM>::Weight(r, radius, z);
      const double g = green.GradientMagnitude(r);
      if (wantHessian)
      {
        this->Volume->EvaluateGradient(x + d, nc, this->FPlus.data(), this->GradPlus.data());
        this->Volume->EvaluateGradient(x - d, nc, this->FMinus.data(), this->GradMinus.data());
      }
      else
      {
        this->Volume->Evaluate(x + d, this->FPlus.data());
        this->Volume->Evaluate(x - d, this->FMinus.data());
      }
      Mat<DIM> m = Mat<DIM>::Zero();
      if (wantHessian)
      {
        m = kernels->RegularPartMatrix(d);
      }
      for (int c = 0; c < nc; ++c)
      {
        const double odd = 0.5 * (this->FPlus[c] - this->FMinus[c]);
        const double even = 0.5 * (this->FPlus[c] + this->FMinus[c]);
        fSample[c] = even;
        for (int i = 0; i < DIM; ++i)
        {
          gradient[c * DIM + i] += weight * g * odd * omega[i];
        }
        if (wantHessian)
        {
          const double control = fBar ? fBar[c] : 0.0;
          Mat<DIM> h = Mat<DIM>::Zero();
          for (int i = 0; i < DIM; ++i)
          {
            const double oddGrad =
              0.5 * (this->GradPlus[c * DIM + i] - this->GradMinus[c * DIM + i]);
            for (int j = 0; j < DIM; ++j)
            {
              h(i, j) = weight * g * oddGrad * omega[j];
            }
          }
          h -= weight * (even - control) * m;
          h -= control * kernels->RegularPartIntegral() * Mat<DIM>::Identity();
          AddSymmetric(h, hessian + c * DIM * DIM);
        }
      }
    }
    if (this->Concentrated.Points && !this->Concentrated.Points->Empty())
    {
      this->Concentrated.Points->ForEachInBall(
        x, radius, [&](const Vec<DIM>& point, const double* s) {
          this->AddConcentrated(point - x, 1.0, s, green, wantHessian ? kernels : nullptr,
            gradient, hessian);
        });
    }
    if (this->Concentrated.Curves && !this->Concentrated.Curves->Empty())
    {
      Vec<DIM> point;
      double inverseDensity = 0.0;
      if (this->Concentrated.Curves->SampleInBall(
            x, radius, rng, this->CurveScratch, point, this->Strength.data(), inverseDensity))
      {
        this->AddConcentrated(point - x, inverseDensity, this->Strength.data(), green,
          wantHessian ? kernels : nullptr, gradient, hessian);
      }
    }
  }

private:
  // ∫ δ_z s ∇G = s ∇G(z − x) and ∫ δ_z s ∇²G = s ∇²_x G(x, z): no
  // integration by parts for a point away from the pole.
  template <class Green>
  void AddConcentrated(const Vec<DIM>& d, double scale, const double* s, const Green& green,
    const BallHessianKernels<DIM>* kernels, double* gradient, double* hessian)
  {
    const Vec<DIM> gradG = green.Gradient(d);
    Mat<DIM> hessG = Mat<DIM>::Zero();
    if (kernels)
    {
      hessG = kernels->PoleHessian(d);
    }
    for (int c = 0; c < this->Components; ++c)
    {
      for (int i = 0; i < DIM; ++i)
      {
        gradient[c * DIM + i] += scale * s[c] * gradG[i];
      }
      if (kernels)
      {
        AddSymmetric(scale * s[c] * hessG, hessian + c * DIM * DIM);
      }
    }
  }

  static void AddSymmetric(const Mat<DIM>& h, double* out)
  {
    for (int i = 0; i < DIM; ++i)
    {
      for (int j = 0; j < DIM; ++j)
      {
        out[i * DIM + j] += 0.5 * (h(i, j) + h(j, i));
      }
    }
  }

  int Components;
  VolumeSource<DIM>* Volume;
  ConcentratedSourceSet<DIM> Concentrated;
  typename CurveSources<DIM>::Scratch CurveScratch;
  std::vector<double> FPlus;
  std::vector<double> FMinus;
  std::vector<double> GradPlus;
  std::vector<double> GradMinus;
  std::vector<double> Strength;
};
} // namespace gridfree

#endif
