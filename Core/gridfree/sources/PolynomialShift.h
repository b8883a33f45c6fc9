// A polynomial control variate for the whole walk: u = P + w.
//
// A walk's spread comes from how the solution varies along its path: for
// Δu − c·u = f with u = g on ∂Ω, a walk's sample minus u(x0) is a sum of
// martingale increments of size |∇u|·R_k (Dynkin's formula), so a solution
// that changes a lot across the domain, or a source that adds a lot over a
// walk whose length varies, gives a wide spread (on the CT workflow 56 °C²
// per walk, two thirds of it the source's). Any known function P may be
// subtracted first: w = u − P solves
//
//   Δw − c·w = f − (ΔP − c·P)    in Ω,       w = g − P    on ∂Ω,
//
// exactly (no approximation: the walks of w are those of u with other data),
// and u = P + w, ∇u = ∇P + ∇w, ∇²u = ∇²P + ∇²w at every point inside. The
// walks of w spread as much as w varies: the closer P is to u, the fewer
// walks a target needs, and a poor P costs walks but never biases.
//
// P is a polynomial of total degree `Degree` in the coordinates scaled to
// [−1, 1] over the boundary's box, fitted by least squares to both sides
// of the problem: P ≈ g at boundary samples and ΔP − c·P ≈ f at source
// samples inside (each set weighted by its count, the source rows by
// `SourceWeight`, a length², so that both misfits are in units of u). A
// polynomial of degree 4–6 follows the broad shape of u (the heating's bulge,
// the boundary data's tilt) and leaves the walks the detail.
//
// Points outside the domain cannot use it: there w = u − P grows like P at
// infinity, which the exterior estimators do not represent.
#ifndef GRIDFREE_SOURCES_POLYNOMIAL_SHIFT_H
#define GRIDFREE_SOURCES_POLYNOMIAL_SHIFT_H

#include <gridfree/math/Vector.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace gridfree
{
template <int DIM>
class PolynomialShift
{
public:
  using Exponents = std::array<int, DIM>;

  // The monomials of total degree at most `degree` (degree 0 to 12), in a
  // fixed order, on the box [low, high] (scaled to [−1, 1]); coefficients 0.
  PolynomialShift(int degree, const Vec<DIM>& low, const Vec<DIM>& high)
    : Degree(degree)
  {
    if (degree < 0 || degree > 12)
    {
      throw std::invalid_argument(
        "the polynomial control variate's degree must be 0 to 12, got " + std::to_string(degree));
    }
    this->Centre = 0.5 * (low + high);
    this->HalfWidth = 0.5 * (high - low).cwiseAbs().maxCoeff();
    if (!(this->HalfWidth > 0.0) || !std::isfinite(this->HalfWidth))
    {
      throw std::invalid_argument("the polynomial control variate needs a box of positive size");
    }
    Exponents e{};
    this->AddMonomials(0, degree, e);
    this->Coefficients.assign(this->Terms.size(), 0.0);
    this->Derive();
  }

  int GetDegree() const { return this->Degree; }
  std::size_t NumberOfTerms() const { return this->Terms.size(); }
  const std::vector<double>& GetCoefficients() const { return this->Coefficients; }
  void SetCoefficients(std::vector<double> c)
  {
    if (c.size() != this->Terms.size())
    {
      throw std::invalid_argument("the polynomial has " + std::to_string(this->Terms.size()) +
        " terms, got " + std::to_string(c.size()) + " coefficients");
    }
    this->Coefficients = std::move(c);
    this->Derive();
  }

  // The screening coefficient c of Operator (set before the walks use it).
  void SetScreening(double screening)
  {
    this->Screening = screening;
    this->Derive();
  }
  double GetScreening() const { return this->Screening; }

  double Value(const Vec<DIM>& x) const { return this->Evaluate(this->Coefficients, x); }

  Vec<DIM> Gradient(const Vec<DIM>& x) const
  {
    Vec<DIM> g;
    for (int i = 0; i < DIM; ++i)
    {
      g[i] = this->Evaluate(this->GradientCoefficients[i], x);
    }
    return g;
  }

  Mat<DIM> Hessian(const Vec<DIM>& x) const
  {
    Mat<DIM> h;
    for (int i = 0; i < DIM; ++i)
    {
      for (int j = 0; j < DIM; ++j)
      {
        h(i, j) = this->Evaluate(this->HessianCoefficients[i * DIM + j], x);
      }
    }
    return h;
  }

  // ΔP − c·P: what the shift takes from the source (c from SetScreening).
  double Operator(const Vec<DIM>& x) const
  {
    return this->Evaluate(this->OperatorCoefficients, x);
  }

  // ∇(ΔP − c·P), for the derivative estimators' source gradients.
  Vec<DIM> OperatorGradient(const Vec<DIM>& x) const
  {
    Vec<DIM> g;
    for (int i = 0; i < DIM; ++i)
    {
      g[i] = this->Evaluate(this->OperatorGradientCoefficients[i], x);
    }
    return g;
  }

  // Least squares: P(b_j) ≈ g_j at boundary samples and ΔP(y_j) − c·P(y_j)
  // ≈ f_j at source samples; each set's rows weighted by 1/√count, the
  // source rows also by sourceWeight (a length²: an error δ of the source
  // moves u by about δ·sourceWeight). Returns false (coefficients left at
  // zero) when the samples do not determine P or a number is not finite.
  bool Fit(const std::vector<Vec<DIM>>& boundaryPoints, const std::vector<double>& boundaryValues,
    const std::vector<Vec<DIM>>& sourcePoints, const std::vector<double>& sourceValues,
    double screening, double sourceWeight)
  {
    const std::size_t m = this->Terms.size();
    if (boundaryPoints.size() != boundaryValues.size() ||
      sourcePoints.size() != sourceValues.size() || boundaryPoints.size() < m)
    {
      return false;
    }
    // The weighted rows themselves, solved by a rank-revealing QR: normal
    // equations would square the condition number of monomials of degree 6
    // (about 1e5 on [−1, 1]³) and lose the fit's last digits.
    const std::size_t rows = boundaryPoints.size() + sourcePoints.size();
    Eigen::MatrixXd design(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(m));
    Eigen::VectorXd right(static_cast<Eigen::Index>(rows));
    Eigen::Index at = 0;
    auto addRows = [&](const std::vector<Vec<DIM>>& points, const std::vector<double>& values,
                     double weight, bool source) {
      if (points.empty())
      {
        return true;
      }
      const double w = weight / std::sqrt(static_cast<double>(points.size()));
      for (std::size_t j = 0; j < points.size(); ++j, ++at)
      {
        if (!points[j].allFinite() || !std::isfinite(values[j]))
        {
          return false;
        }
        const Vec<DIM> y = (points[j] - this->Centre) / this->HalfWidth;
        for (std::size_t t = 0; t < m; ++t)
        {
          design(at, static_cast<Eigen::Index>(t)) = w *
            (source ? this->ScaledOperator(this->Terms[t], y, screening)
                    : MonomialDerivative(this->Terms[t], Exponents{}, y));
        }
        right[at] = w * values[j];
      }
      return true;
    };
    if (!addRows(boundaryPoints, boundaryValues, 1.0, false) ||
      !addRows(sourcePoints, sourceValues, sourceWeight, true))
    {
      return false;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> solve(design);
    if (solve.rank() < static_cast<Eigen::Index>(m))
    {
      return false;
    }
    const Eigen::VectorXd c = solve.solve(right);
    if (!c.allFinite())
    {
      return false;
    }
    this->Coefficients.assign(c.data(), c.data() + c.size());
    this->Screening = screening;
    this->Derive();
    return true;
  }

private:
  // Σ_t a_t Π y_i^{e_i}, y = (x − centre)/halfWidth, from a table of powers.
  double Evaluate(const std::vector<double>& a, const Vec<DIM>& x) const
  {
    std::array<std::array<double, 13>, DIM> powers;
    for (int i = 0; i < DIM; ++i)
    {
      const double y = (x[i] - this->Centre[i]) / this->HalfWidth;
      powers[i][0] = 1.0;
      for (int k = 1; k <= this->Degree; ++k)
      {
        powers[i][k] = powers[i][k - 1] * y;
      }
    }
    double sum = 0.0;
    for (std::size_t t = 0; t < this->Terms.size(); ++t)
    {
      double term = a[t];
      for (int i = 0; i < DIM; ++i)
      {
        term *= powers[i][this->Terms[t][i]];
      }
      sum += term;
    }
    return sum;
  }

  // The coefficients of ∂^α P in the same monomials (world units).
  std::vector<double> DerivativeCoefficients(const std::vector<double>& a, const Exponents& alpha) const
  {
    std::vector<double> out(this->Terms.size(), 0.0);
    int order = 0;
    for (int i = 0; i < DIM; ++i)
    {
      order += alpha[i];
    }
    const double scale = std::pow(this->HalfWidth, -order);
    for (std::size_t t = 0; t < this->Terms.size(); ++t)
    {
      Exponents lowered = this->Terms[t];
      double factor = a[t] * scale;
      for (int i = 0; i < DIM && factor != 0.0; ++i)
      {
        for (int k = 0; k < alpha[i]; ++k)
        {
          factor *= static_cast<double>(lowered[i]);
          lowered[i] -= 1;
        }
      }
      if (factor != 0.0)
      {
        out[this->IndexOf(lowered)] += factor;
      }
    }
    return out;
  }

  std::size_t IndexOf(const Exponents& e) const
  {
    for (std::size_t t = 0; t < this->Terms.size(); ++t)
    {
      if (this->Terms[t] == e)
      {
        return t;
      }
    }
    throw std::logic_error("a monomial outside the basis");
  }

  void Derive()
  {
    for (int i = 0; i < DIM; ++i)
    {
      this->GradientCoefficients[i] = this->DerivativeCoefficients(this->Coefficients, Unit(i));
      for (int j = 0; j < DIM; ++j)
      {
        Exponents a = Unit(i);
        a[j] += 1;
        this->HessianCoefficients[i * DIM + j] =
          this->DerivativeCoefficients(this->Coefficients, a);
      }
    }
    this->OperatorCoefficients = this->Coefficients;
    for (double& a : this->OperatorCoefficients)
    {
      a *= -this->Screening;
    }
    for (int i = 0; i < DIM; ++i)
    {
      const std::vector<double>& second = this->HessianCoefficients[i * DIM + i];
      for (std::size_t t = 0; t < second.size(); ++t)
      {
        this->OperatorCoefficients[t] += second[t];
      }
    }
    for (int i = 0; i < DIM; ++i)
    {
      this->OperatorGradientCoefficients[i] =
        this->DerivativeCoefficients(this->OperatorCoefficients, Unit(i));
    }
  }

  static Exponents Unit(int i)
  {
    Exponents e{};
    e[i] = 1;
    return e;
  }

  void AddMonomials(int axis, int left, Exponents& e)
  {
    if (axis == DIM)
    {
      this->Terms.push_back(e);
      return;
    }
    for (int p = 0; p <= left; ++p)
    {
      e[axis] = p;
      this->AddMonomials(axis + 1, left - p, e);
    }
    e[axis] = 0;
  }

  // ∂^α of Π y_i^{e_i} at y (scaled coordinates).
  static double MonomialDerivative(const Exponents& e, const Exponents& alpha, const Vec<DIM>& y)
  {
    double value = 1.0;
    for (int i = 0; i < DIM; ++i)
    {
      if (alpha[i] > e[i])
      {
        return 0.0;
      }
      double factor = 1.0;
      for (int k = 0; k < alpha[i]; ++k)
      {
        factor *= static_cast<double>(e[i] - k);
      }
      for (int k = 0; k < e[i] - alpha[i]; ++k)
      {
        factor *= y[i];
      }
      value *= factor;
    }
    return value;
  }

  // (Δ − c) of a monomial, in the world's units, at scaled y.
  double ScaledOperator(const Exponents& e, const Vec<DIM>& y, double screening) const
  {
    double value = -screening * MonomialDerivative(e, Exponents{}, y);
    const double s2 = this->HalfWidth * this->HalfWidth;
    for (int i = 0; i < DIM; ++i)
    {
      Exponents a{};
      a[i] = 2;
      value += MonomialDerivative(e, a, y) / s2;
    }
    return value;
  }

  int Degree = 0;
  Vec<DIM> Centre = Vec<DIM>::Zero();
  double HalfWidth = 1.0;
  std::vector<Exponents> Terms;
  double Screening = 0.0;
  std::vector<double> Coefficients;
  // Derived once per fit: ∂_i P, ∂_i∂_j P, ΔP − c·P and its gradient.
  std::array<std::vector<double>, DIM> GradientCoefficients;
  std::array<std::vector<double>, DIM * DIM> HessianCoefficients;
  std::vector<double> OperatorCoefficients;
  std::array<std::vector<double>, DIM> OperatorGradientCoefficients;
};
} // namespace gridfree

#endif
