// Manufactured solutions of ∇·(α∇u) − σu = f (VaryingCoefficients.h): a
// chosen u with its gradient and Laplacian, a chosen α with its gradient and
// Laplacian, a chosen σ, and f = αΔu + ∇α·∇u − σu, so the exact solution of
// the Dirichlet problem with g = u is u.
#ifndef GRIDFREE_TESTING_MANUFACTURED_COEFFICIENTS_H
#define GRIDFREE_TESTING_MANUFACTURED_COEFFICIENTS_H

#include <gridfree/coefficients/VaryingCoefficients.h>
#include <gridfree/math/Vector.h>

#include <cmath>
#include <functional>

namespace gridfree
{
namespace testing
{
// A function with its gradient and Laplacian.
template <int DIM>
struct SmoothFunction
{
  std::function<double(const Vec<DIM>&)> Value;
  std::function<Vec<DIM>(const Vec<DIM>&)> Gradient;
  std::function<double(const Vec<DIM>&)> Laplacian;
};

template <int DIM>
struct ManufacturedCase
{
  SmoothFunction<DIM> U;
  SmoothFunction<DIM> Alpha;
  std::function<double(const Vec<DIM>&)> Sigma = [](const Vec<DIM>&) { return 0.0; };
};

// The coefficients of a manufactured case, f from u.
template <int DIM>
class ManufacturedField final : public CoefficientField<DIM>
{
public:
  explicit ManufacturedField(ManufacturedCase<DIM> c)
    : Case(std::move(c))
  {
  }
  void Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const override
  {
    out.Alpha = this->Case.Alpha.Value(x);
    out.AlphaGradient = this->Case.Alpha.Gradient(x);
    out.AlphaLaplacian = this->Case.Alpha.Laplacian(x);
    out.Absorption = this->Case.Sigma(x);
    out.Source = out.Alpha * this->Case.U.Laplacian(x) +
      out.AlphaGradient.dot(this->Case.U.Gradient(x)) - out.Absorption * this->Case.U.Value(x);
  }

private:
  ManufacturedCase<DIM> Case;
};

// Coefficients from a plain function (tests of bad or special fields).
template <int DIM>
class CallableCoefficients final : public CoefficientField<DIM>
{
public:
  using Function = std::function<void(const Vec<DIM>&, CoefficientSample<DIM>&)>;
  explicit CallableCoefficients(Function f)
    : F(std::move(f))
  {
  }
  void Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const override { this->F(x, out); }

private:
  Function F;
};

// α = a + b·exp(−|x − c|²/w²): a smooth bump (σ′ < 0 on its top, where α
// is concave, > 0 on its flanks).
template <int DIM>
SmoothFunction<DIM> GaussianBump(double a, double b, const Vec<DIM>& c, double w)
{
  SmoothFunction<DIM> f;
  auto e = [=](const Vec<DIM>& x) { return std::exp(-(x - c).squaredNorm() / (w * w)); };
  f.Value = [=](const Vec<DIM>& x) { return a + b * e(x); };
  f.Gradient = [=](const Vec<DIM>& x) -> Vec<DIM> { return (-2.0 * b * e(x) / (w * w)) * (x - c); };
  f.Laplacian = [=](const Vec<DIM>& x) {
    const double r2 = (x - c).squaredNorm() / (w * w);
    return b * e(x) * (4.0 * r2 - 2.0 * DIM) / (w * w);
  };
  return f;
}

// α = a + b·tanh((x₀ − t)/w): a smooth step across the plane x₀ = t, from
// a − b to a + b over a width of about 2w (two tissues and their interface).
template <int DIM>
SmoothFunction<DIM> SmoothStep(double a, double b, double t, double w)
{
  SmoothFunction<DIM> f;
  f.Value = [=](const Vec<DIM>& x) { return a + b * std::tanh((x[0] - t) / w); };
  f.Gradient = [=](const Vec<DIM>& x) -> Vec<DIM> {
    const double th = std::tanh((x[0] - t) / w);
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = b * (1.0 - th * th) / w;
    return g;
  };
  f.Laplacian = [=](const Vec<DIM>& x) {
    const double th = std::tanh((x[0] - t) / w);
    return -2.0 * b * th * (1.0 - th * th) / (w * w);
  };
  return f;
}

// u = e^{x₀} cos(x₁) + x₁ x_{n−1} + 1/2 (not harmonic in 2D: Δ(x₁²) = 2).
template <int DIM>
SmoothFunction<DIM> ExpCosSolution()
{
  SmoothFunction<DIM> f;
  f.Value = [](const Vec<DIM>& x) { return std::exp(x[0]) * std::cos(x[1]) + x[1] * x[DIM - 1] + 0.5; };
  f.Gradient = [](const Vec<DIM>& x) -> Vec<DIM> {
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = std::exp(x[0]) * std::cos(x[1]);
    g[1] = -std::exp(x[0]) * std::sin(x[1]);
    g[1] += x[DIM - 1];
    g[DIM - 1] += x[1];
    return g;
  };
  f.Laplacian = [](const Vec<DIM>&) { return DIM == 2 ? 2.0 : 0.0; };
  return f;
}

// u = sin(2x₀) + x₁² − x_{n−1}/2 + 1.
template <int DIM>
SmoothFunction<DIM> SineSolution()
{
  SmoothFunction<DIM> f;
  f.Value = [](const Vec<DIM>& x) { return std::sin(2.0 * x[0]) + x[1] * x[1] - 0.5 * x[DIM - 1] + 1.0; };
  f.Gradient = [](const Vec<DIM>& x) -> Vec<DIM> {
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = 2.0 * std::cos(2.0 * x[0]);
    g[1] = 2.0 * x[1];
    g[DIM - 1] += -0.5;
    return g;
  };
  f.Laplacian = [](const Vec<DIM>& x) { return -4.0 * std::sin(2.0 * x[0]) + 2.0; };
  return f;
}
} // namespace testing
} // namespace gridfree

#endif
