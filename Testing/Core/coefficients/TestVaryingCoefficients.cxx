// Tests of gridfree/coefficients/VaryingCoefficients.h: the change of
// variables U = √α u turns ∇·(α∇u) − σu = f into ΔU − σ′U = f′ with the
// σ′ and f′ of Transform, checked by finite differences of U for
// manufactured α, σ, u in 2D and 3D.
#include <gridfree/coefficients/VaryingCoefficients.h>
#include "ManufacturedCoefficients.h"

#include <gtest/gtest.h>

#include <random>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
template <int DIM>
void ExpectTransformSolves(const ManufacturedCase<DIM>& with)
{
  const ManufacturedField<DIM> field(with);
  auto bigU = [&](const Vec<DIM>& x) { return std::sqrt(with.Alpha.Value(x)) * with.U.Value(x); };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-0.8, 0.8);
  const double h = 1e-3;
  for (int trial = 0; trial < 50; ++trial)
  {
    Vec<DIM> x;
    for (int i = 0; i < DIM; ++i)
    {
      x[i] = unit(rng);
    }
    double laplacian = 0.0;
    for (int i = 0; i < DIM; ++i)
    {
      Vec<DIM> e = Vec<DIM>::Zero();
      e[i] = h;
      laplacian += (bigU(x + e) - 2.0 * bigU(x) + bigU(x - e)) / (h * h);
    }
    CoefficientSample<DIM> c;
    field.Evaluate(x, c);
    const TransformedCoefficients t = Transform(c);
    EXPECT_NEAR(t.SqrtAlpha, std::sqrt(c.Alpha), 1e-15);
    // ΔU − σ′U = f′ to the finite differences' accuracy (h² ~ 1e-6).
    EXPECT_NEAR(laplacian - t.Screening * bigU(x), t.Source, 2e-4 * (1.0 + std::abs(t.Source)));
  }
}
} // namespace

TEST(VaryingCoefficients, TransformSolvesTheScreenedEquation)
{
  ManufacturedCase<3> bump;
  bump.U = ExpCosSolution<3>();
  bump.Alpha = GaussianBump<3>(1.0, 1.5, Vec<3>(0.2, 0.0, 0.0), 0.4);
  bump.Sigma = [](const Vec<3>& x) { return 1.0 + x[0] * x[0]; };
  ExpectTransformSolves<3>(bump);

  ManufacturedCase<2> step;
  step.U = SineSolution<2>();
  step.Alpha = SmoothStep<2>(5.5, 4.5, 0.1, 0.3);
  step.Sigma = [](const Vec<2>& x) { return 3.0 + x[1]; };
  ExpectTransformSolves<2>(step);
}

// σ′ of a constant α is σ/α; of α = e^{a·x} it is σ/α + |a|²/4.
TEST(VaryingCoefficients, ClosedFormScreenings)
{
  CoefficientSample<3> c;
  c.Alpha = 4.0;
  c.Absorption = 2.0;
  c.Source = 6.0;
  TransformedCoefficients t = Transform(c);
  EXPECT_DOUBLE_EQ(t.Screening, 0.5);
  EXPECT_DOUBLE_EQ(t.Source, 3.0);
  const Vec<3> a(0.3, -1.2, 2.0);
  c.AlphaGradient = a * c.Alpha;
  c.AlphaLaplacian = a.squaredNorm() * c.Alpha;
  t = Transform(c);
  EXPECT_NEAR(t.Screening, 0.5 + a.squaredNorm() / 4.0, 1e-14);
}
